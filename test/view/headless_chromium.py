"""Debian's Chromium, headless, driven by Debian's python3-selenium and chromium-driver: loads a page of
`hullmap view` from file:// and reads it back (its window.hullmapView summary, its errors, a screenshot).

Used by test/view/browser_test.py, bench/view_scale.py and docs/img/view_picture.py. The flags are the
ones known to render WebGL in a container without a GPU or a display: software WebGL (SwiftShader
through ANGLE), no sandbox, nothing fetched from the network, a fresh profile each time.
"""
import os
import shutil
import tempfile
import time

# Debian's; HULLMAP_CHROMIUM and HULLMAP_CHROMEDRIVER name others.
CHROMIUM = os.environ.get("HULLMAP_CHROMIUM", "/usr/bin/chromium")
CHROMEDRIVER = os.environ.get("HULLMAP_CHROMEDRIVER", "/usr/bin/chromedriver")
THREE_DIR = "/usr/share/javascript/three"
FLAGS = ["--headless=new", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
         "--disable-background-networking", "--disable-component-update", "--disable-sync", "--no-first-run",
         "--disable-dev-shm-usage", "--hide-scrollbars"]


def missing():
    """Why pages cannot be loaded here (the Debian package to install), or None."""
    if not os.access(CHROMIUM, os.X_OK):
        return CHROMIUM + " not found: install Debian's chromium (./setup.sh test does)"
    if not os.access(CHROMEDRIVER, os.X_OK):
        return CHROMEDRIVER + " not found: install Debian's chromium-driver (./setup.sh test does)"
    for module, package in (("selenium", "python3-selenium"), ("PIL", "python3-pil"), ("numpy", "python3-numpy")):
        try:
            __import__(module)
        except ImportError:
            return "python3 module %s not found: install Debian's %s (./setup.sh test does)" % (module, package)
    if not os.path.exists(os.path.join(THREE_DIR, "three.min.js")):
        return THREE_DIR + "/three.min.js not found: install Debian's libjs-three (./setup.sh test does)"
    return None


def decode_png(data):
    """A PNG (Chromium's screenshots) as a numpy array (height, width, 3) of RGB."""
    import io
    import numpy
    from PIL import Image
    return numpy.asarray(Image.open(io.BytesIO(data)).convert("RGB")).astype(numpy.int32)


class Browser:
    """One headless Chromium; `with Browser() as b: summary = b.load(path)`."""

    def __init__(self, width=1280, height=800, script_timeout=120, flags=()):
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
        self.profile = tempfile.mkdtemp(prefix="hullmap-chromium-")
        options = webdriver.ChromeOptions()
        options.binary_location = CHROMIUM
        for flag in FLAGS + list(flags) + ["--user-data-dir=" + self.profile, "--window-size=%d,%d" % (width, height)]:
            options.add_argument(flag)
        options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
        self.driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)
        # The page gets exactly width x height CSS pixels (the window's own frame takes some of
        # --window-size).
        self.driver.execute_cdp_cmd("Emulation.setDeviceMetricsOverride",
                                    {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False})
        self.driver.set_page_load_timeout(max(120, script_timeout))
        self.driver.set_script_timeout(script_timeout)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.quit()

    def quit(self):
        if self.driver is not None:
            self.driver.quit()
            self.driver = None
        shutil.rmtree(self.profile, ignore_errors=True)

    def load(self, path, timeout=60.0):
        """Opens `path` from file:// and waits for window.hullmapView.ready (or an error). Returns the
        page's errors (its own list and the console's SEVERE messages) and the summary."""
        self.driver.get("file://" + os.path.abspath(path))
        deadline = time.time() + timeout
        while True:
            ready = self.driver.execute_script(
                "return !!(window.hullmapView && window.hullmapView.ready) || "
                "(window.hullmapErrors || []).length > 0")
            if ready or time.time() > deadline:
                break
            time.sleep(0.05)
        return self.errors(), self.summary()

    def errors(self):
        page = self.driver.execute_script("return (window.hullmapErrors || []).slice()")
        console = [e["message"] for e in self.driver.get_log("browser") if e.get("level") == "SEVERE"]
        return page + console

    def summary(self):
        """window.hullmapView's data (its functions left out), or None when the page did not make one."""
        return self.driver.execute_script(
            "var v = window.hullmapView; if (!v) return null; var out = {};"
            "Object.keys(v).forEach(function (k) { if (typeof v[k] !== 'function') out[k] = v[k]; });"
            "out.layers = v.layers ? v.layers() : null; return out;")

    def run(self, script, *args):
        return self.driver.execute_script(script, *args)

    def screenshot(self):
        """The window as a numpy array (height, width, 3)."""
        return decode_png(self.driver.get_screenshot_as_png())

    def screenshot_png(self):
        return self.driver.get_screenshot_as_png()
