"""docs/PYTHON.md's example and the README's Python lines run as written, from the checkout, and print
what the text says."""
import re
import subprocess
import sys

from conftest import SOURCE


def block(document, marker):
    """The ```python block right after `marker` in `document`."""
    text = (SOURCE / document).read_text()
    assert marker in text
    found = re.match(r"\s*```python\n(.*?)```", text[text.index(marker) + len(marker):], re.S)
    assert found, f"no python block after {marker} in {document}"
    return found.group(1)


def run(code):
    done = subprocess.run([sys.executable, "-c", code], cwd=SOURCE, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_the_example_runs_as_written():
    code = block("docs/PYTHON.md", "<!-- example: test/python/test_docs.py runs this block as written, from the checkout -->")
    assert 8 <= len([line for line in code.splitlines() if line.strip()]) <= 12
    first, second = run(code).splitlines()
    assert first.startswith("<hullmap.Map: 9 obstacles in 38 convex parts") and " eps " in first
    assert re.fullmatch(r"\d+\.\d\d m in \d+ legs, clearance \d\.\d{3} m", second)


def test_the_readme_tour_runs_as_written():
    out = run(block("README.md", "<!-- tour: test/python/test_docs.py runs this block -->"))
    # maps/simple/segments.txt: some segments collide, some are clear.
    assert "True" in out and "False" in out


def test_the_build_tree_imports_as_the_set_up_says():
    done = subprocess.run([sys.executable, "-c", "import hullmap; print(hullmap.__file__)"], cwd="/",
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip().endswith("python/hullmap/__init__.py")
