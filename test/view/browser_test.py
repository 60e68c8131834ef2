#!/usr/bin/env python3
"""`hullmap view` in a real browser: Debian's Chromium, headless, loads the page of maps/room (built at
its defaults, with a path from `hullmap plan`, a path through the furniture, its roadmap and ground
truth) from file:// and the page's summary object, window.hullmapView, is compared with the build's
report.json, obstacles.json, voxels.csv and `hullmap check --json`. A screenshot must not be blank and
must show the parts' colours and the colliding path's red; a click on a part must name it; any
JavaScript error fails.

Environment: HULLMAP_BINARY, HULLMAP_SOURCE_DIR, HULLMAP_TEST_TMP. Exits 77 (CTest: skipped), saying
why, where Chromium, chromium-driver, python3-selenium or libjs-three is missing.
"""
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import headless_chromium  # noqa: E402

HULLMAP = os.environ["HULLMAP_BINARY"]
SOURCE = os.environ["HULLMAP_SOURCE_DIR"]
TMP = os.path.join(os.environ["HULLMAP_TEST_TMP"], "view_browser")
ROOM = os.path.join(SOURCE, "maps", "room")
RADIUS = 0.3

browser = None
build = None


def hullmap(*args, ok=(0,)):
    r = subprocess.run([HULLMAP, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode not in ok:
        raise AssertionError("hullmap %s exited %d: %s" % (" ".join(args), r.returncode, r.stderr))
    return r.stdout


def setUpModule():
    global browser, build
    shutil.rmtree(TMP, ignore_errors=True)
    os.makedirs(TMP)
    build = os.path.join(TMP, "room")
    hullmap("build", os.path.join(ROOM, "map_points.txt"), "--trajectory", os.path.join(ROOM, "KeyFrameTrajectory.txt"),
            "--align", os.path.join(ROOM, "reference_trajectory.txt"), "-o", build)
    hullmap("plan", build, "--from", "-3,-3,1", "--to", "3,3,1.2", "--radius", str(RADIUS),
            "-o", os.path.join(TMP, "plan.txt"))
    # From the south-west corner over the box by the south wall (obstacle ids depend on the build).
    with open(os.path.join(TMP, "through.txt"), "w") as f:
        f.write("# x y z\n-3 -3 1\n0 -2.3 0.6\n3 3 1.2\n")
    hullmap("roadmap", build, "--radius", str(RADIUS), "--band", "0.8,1.2", "-o", os.path.join(TMP, "roadmap.json"))
    hullmap("view", build, "-o", os.path.join(TMP, "room.html"), "--path", os.path.join(TMP, "plan.txt"),
            "--path", os.path.join(TMP, "through.txt"), "-r", str(RADIUS), "--roadmap", os.path.join(TMP, "roadmap.json"),
            "--truth", os.path.join(ROOM, "ground_truth.json"))
    browser = headless_chromium.Browser(1280, 800)


def tearDownModule():
    if browser is not None:
        browser.quit()


def read_json(name):
    with open(os.path.join(build, name)) as f:
        return json.load(f)


def load(page):
    errors, summary = browser.load(page)
    if errors:
        raise AssertionError("JavaScript errors in %s: %s" % (page, errors))
    if summary is None or not summary.get("ready"):
        raise AssertionError("%s did not finish drawing (window.hullmapView %s)" % (page, summary))
    return summary


def near(a, b, tolerance):
    return abs(a - b) <= tolerance * max(1.0, abs(a), abs(b))


def pixels_near(image, rgb, distance):
    import numpy
    d = numpy.abs(image - numpy.array(rgb)).sum(axis=2)
    return d <= distance


def inside(p, polygon):
    """Whether p's (x, y) lies in the convex counter-clockwise polygon (or on its edge)."""
    for (ax, ay), (bx, by) in zip(polygon, polygon[1:] + polygon[:1]):
        if (bx - ax) * (p[1] - ay) - (by - ay) * (p[0] - ax) < -1e-9:
            return False
    return True


def hex_rgb(text):
    return [int(text[i:i + 2], 16) for i in (1, 3, 5)]


class Summary(unittest.TestCase):
    """window.hullmapView against the build's files."""

    @classmethod
    def setUpClass(cls):
        cls.view = load(os.path.join(TMP, "room.html"))
        cls.report = read_json("report.json")
        cls.obstacles = read_json("obstacles.json")["obstacles"]

    def test_the_page_is_the_builds_counts_frame_and_parameters(self):
        v, report = self.view, self.report
        self.assertEqual(v["format"], "hullmap-view/1")
        self.assertEqual(v["three_revision"], "111")
        self.assertEqual(v["frame"], report["frame"])
        self.assertEqual(v["parameters"], report["parameters"])
        self.assertEqual(v["voxels"]["total"], report["octree"]["occupied_voxels"])
        self.assertEqual(v["voxels"]["noise"], report["clusters"]["noise_voxels"])
        self.assertEqual(v["voxels"]["floor"], report["floor"]["voxels"])
        self.assertEqual(v["voxels"]["ceiling"], report["ceiling"]["voxels"])
        finest = v["voxels"]["levels"][0]
        self.assertEqual((finest["factor"], finest["instances"]), (1, report["octree"]["occupied_voxels"]))
        self.assertEqual(len(v["obstacles"]), report["obstacles"])
        self.assertEqual(len(v["parts"]), report["parts"]["count"])
        self.assertEqual(v["keyframes"], report["keyframes"])
        self.assertEqual(v["floor"], report["floor"]["plane"])
        self.assertEqual(v["layers"], {name: True for name in ("voxels", "noise", "surfaces", "parts", "floor", "keyframes",
                                                               "paths", "roadmap", "truth", "grid")})

    def test_every_voxel_of_voxels_csv_is_drawn_where_it_is(self):
        # Per label: the number of cubes and the sum of their centres, decoded by the page from its
        # 16-bit cells, against voxels.csv.
        expected = {}
        with open(os.path.join(build, "voxels.csv")) as f:
            for row in csv.DictReader(f):
                e = expected.setdefault(str(int(row["label"])), [0, 0.0, 0.0, 0.0])
                e[0] += 1
                for a, key in enumerate("xyz"):
                    e[1 + a] += float(row[key])
        drawn = self.view["voxels"]["labels"]
        self.assertEqual(set(drawn), set(expected))
        for label, e in expected.items():
            self.assertEqual(drawn[label]["cells"], e[0], label)
            for a in range(3):
                self.assertTrue(near(drawn[label]["sum"][a], e[1 + a], 1e-7), (label, a, drawn[label]["sum"], e))

    def test_parts_are_those_of_obstacles_json_with_their_ids_volumes_and_voxels(self):
        expected = [(o["id"], k, p["volume"], p["voxel_count"], len(p["hull"]["vertices"]), len(p["hull"]["triangles"]))
                    for o in self.obstacles for k, p in enumerate(o["parts"])]
        got = [(p["obstacle"], p["part"], p["volume"], p["voxels"], p["vertices"], p["triangles"]) for p in self.view["parts"]]
        self.assertEqual(got, expected)
        self.assertEqual([o["id"] for o in self.view["obstacles"]], [o["id"] for o in self.obstacles])

    def test_paths_are_checked_as_hullmap_check_checks_them(self):
        paths = self.view["paths"]
        self.assertEqual([p["name"] for p in paths], ["plan.txt", "through.txt"])
        for p in paths:
            lines = hullmap("check", build, "-r", str(RADIUS), "--json", "--path", os.path.join(TMP, p["name"]),
                            ok=(0, 1)).splitlines()
            expected = [json.loads(line) for line in lines]
            self.assertEqual(len(p["segments"]), len(expected))
            for s, e in zip(p["segments"], expected):
                for key in ("collides", "obstacle", "surface", "t", "clearance"):
                    self.assertEqual(s[key], e[key], (p["name"], key))
                self.assertEqual(s["part"], e.get("part", -1))
            colliding = [i for i, e in enumerate(expected) if e["collides"]]
            self.assertEqual(p["collides"], bool(colliding))
            self.assertEqual(p["first_colliding_segment"], colliding[0] if colliding else None)
        self.assertFalse(paths[0]["collides"], "plan's path is clear by construction")
        self.assertTrue(paths[1]["collides"])
        hit = paths[1]["segments"][paths[1]["first_colliding_segment"]]
        self.assertEqual(paths[1]["hit"], {"obstacle": hit["obstacle"], "part": hit["part"], "surface": hit["surface"]})

    def test_roadmap_and_truth_are_drawn_whole(self):
        with open(os.path.join(TMP, "roadmap.json")) as f:
            roadmap = json.load(f)
        self.assertEqual(self.view["roadmap"]["nodes"], len(roadmap["nodes"]))
        self.assertEqual(self.view["roadmap"]["edges"], len(roadmap["edges"]))
        with open(os.path.join(ROOM, "ground_truth.json")) as f:
            truth = json.load(f)
        self.assertEqual(self.view["truth"]["shapes"], len(truth["obstacles"]))


class Screen(unittest.TestCase):
    """What the page draws, from screenshots, and what clicking and the buttons do."""

    @classmethod
    def setUpClass(cls):
        cls.view = load(os.path.join(TMP, "room.html"))

    def test_the_screenshot_is_not_blank_and_shows_the_parts_colours_and_the_collision(self):
        import numpy
        browser.run("hullmapView.setCamera('free')")
        image = browser.screenshot()
        background = pixels_near(image, [255, 255, 255], 12)
        self.assertLess(background.mean(), 0.8, "mostly white: nothing drawn")
        self.assertGreater(len(numpy.unique(image.reshape(-1, 3), axis=0)), 500)
        # The parts alone (voxels, floor and grid hidden with their check boxes, as a user would):
        # each obstacle's colour is on the screen, from its parts' edges.
        for name in ("voxels", "noise", "surfaces", "floor", "grid", "truth", "roadmap", "keyframes"):
            browser.driver.find_element("id", "layer-" + name).click()
        self.assertEqual(browser.run("return hullmapView.layers()"),
                         dict({name: False for name in ("voxels", "noise", "surfaces", "floor", "grid", "truth", "roadmap",
                                                        "keyframes")}, parts=True, paths=True))
        image = browser.screenshot()
        for o in self.view["obstacles"]:
            count = int(pixels_near(image, hex_rgb(o["colour"]), 30).sum())
            self.assertGreater(count, 30, "obstacle %d's colour %s: %d pixels" % (o["id"], o["colour"], count))
        # The colliding path is red from its first contact on, and the contact is marked there.
        path = self.view["paths"][1]
        x, y, _ = browser.run("return hullmapView.project(arguments[0])", path["first_contact"])
        red = (image[:, :, 0] > 220) & (image[:, :, 1] < 50) & (image[:, :, 2] < 50)
        h, w = red.shape
        y0, y1, x0, x1 = max(0, int(y) - 25), min(h, int(y) + 25), max(0, int(x) - 25), min(w, int(x) + 25)
        self.assertGreater(int(red[y0:y1, x0:x1].sum()), 40, "red around the first contact at (%d, %d)" % (x, y))
        # That red is the path's and its hit part's outline (nothing else is drawn in it): hidden with
        # them, none is left.
        browser.driver.find_element("id", "layer-paths").click()
        browser.driver.find_element("id", "layer-parts").click()
        image = browser.screenshot()
        red = (image[:, :, 0] > 220) & (image[:, :, 1] < 50) & (image[:, :, 2] < 50)
        self.assertLess(int(red.sum()), 5, "red without the paths and parts")
        for name in ("voxels", "noise", "surfaces", "floor", "grid", "truth", "roadmap", "keyframes", "paths", "parts"):
            browser.run("hullmapView.setLayer(arguments[0], true)", name)
        self.assertEqual(browser.errors(), [])

    def test_clicking_a_part_shows_its_obstacle_part_volume_and_voxels(self):
        from selenium.webdriver.common.action_chains import ActionChains
        browser.run("hullmapView.setCamera('top')")
        self.assertEqual(browser.run("return hullmapView.camera"), "top")
        # The centre of the part the colliding path hits first, seen from above: the part clicked is
        # the topmost there, one whose footprint holds that point.
        hit = self.view["paths"][1]["hit"]
        parts = {(p["obstacle"], p["part"]): p for p in self.view["parts"]}
        footprints = {(o["id"], k): p["footprint"]["polygon"] for o in read_json("obstacles.json")["obstacles"]
                      for k, p in enumerate(o["parts"])}
        centroid = [o for o in read_json("obstacles.json")["obstacles"] if o["id"] == hit["obstacle"]][0] \
            ["parts"][hit["part"]]["centroid"]
        x, y, _ = browser.run("return hullmapView.project(arguments[0])", centroid)
        canvas = browser.driver.find_element("id", "hullmap-canvas")
        rect = browser.run("var r = arguments[0].getBoundingClientRect(); return [r.left, r.top, r.width, r.height]", canvas)
        ActionChains(browser.driver).move_to_element_with_offset(canvas, int(x - rect[0] - rect[2] / 2),
                                                                 int(y - rect[1] - rect[3] / 2)).click().perform()
        selected = browser.run("return hullmapView.selected")
        self.assertIsNotNone(selected, "a click on the first contact selects a part")
        part = parts[(selected["obstacle"], selected["part"])]
        self.assertEqual(selected["volume"], part["volume"])
        self.assertEqual(selected["voxels"], part["voxels"])
        info = browser.driver.find_element("id", "hullmap-info").text
        self.assertIn("obstacle %d part %d" % (selected["obstacle"], selected["part"]), info)
        self.assertIn("%d voxels" % part["voxels"], info)
        self.assertTrue(inside(centroid, footprints[(selected["obstacle"], selected["part"])]),
                        "the part clicked, %s, lies under the point clicked" % selected)
        # A click on empty space (the right edge of the window, outside the room) clears it.
        ActionChains(browser.driver).move_to_element_with_offset(canvas, int(rect[2] / 2 - 5), 0).click().perform()
        self.assertIsNone(browser.run("return hullmapView.selected"))
        for name in ("side", "free"):
            browser.driver.find_element("id", "camera-" + name).click()
            self.assertEqual(browser.run("return hullmapView.camera"), name)
        self.assertEqual(browser.errors(), [])


class Failures(unittest.TestCase):
    """The harness sees a broken page."""

    def test_a_page_with_a_javascript_error_is_refused(self):
        with open(os.path.join(TMP, "room.html")) as f:
            html = f.read()
        broken = os.path.join(TMP, "broken.html")
        # The same page with its data cut short: the viewer's JSON.parse throws.
        start = html.index('id="hullmap-data">') + len('id="hullmap-data">')
        with open(broken, "w") as f:
            f.write(html[:start] + html[start:start + 1000] + html[html.index("</script>", start):])
        errors, summary = browser.load(broken)
        self.assertTrue(errors, "the error is seen")
        self.assertFalse(summary and summary.get("ready"))
        with self.assertRaises(AssertionError):
            load(broken)

    def test_without_webgl_the_page_says_so_and_fails(self):
        with headless_chromium.Browser(800, 600, flags=["--disable-3d-apis"]) as plain:
            errors, summary = plain.load(os.path.join(TMP, "room.html"))
            self.assertTrue(any("WebGL" in e for e in errors), errors)
            self.assertFalse(summary["ready"])
            self.assertIn("no WebGL", plain.driver.find_element("id", "hullmap-no-webgl").text)


class Detail(unittest.TestCase):
    """The levels of detail: every voxel at the finest unless over the budget, the level drawn chosen
    from a frame, another picked in the legend."""

    def test_a_build_over_the_budget_is_held_merged_and_the_page_says_so(self):
        page = os.path.join(TMP, "merged.html")
        hullmap("view", build, "-o", page, "--max-instances", "3000")
        v = load(page)
        finest = v["voxels"]["levels"][0]
        self.assertGreater(finest["factor"], 1)
        self.assertLessEqual(finest["instances"], 3000)
        self.assertEqual(v["voxels"]["total"], read_json("report.json")["octree"]["occupied_voxels"])
        self.assertEqual(sum(l["cells"] for l in v["voxels"]["labels"].values()), finest["instances"])
        legend = browser.driver.find_element("id", "hullmap-legend").text
        self.assertIn("its finest level merges them into %s cells" % format(finest["instances"], ","), legend)

    def test_the_level_of_detail_is_chosen_from_a_frame_and_picked_in_the_legend(self):
        from selenium.webdriver.support.ui import Select
        v = load(os.path.join(TMP, "room.html"))
        levels = v["voxels"]["levels"]
        self.assertGreater(len(levels), 1, "maps/room holds more than the coarsest level's 10,000 cubes")
        self.assertEqual([l["factor"] for l in levels], [2 ** k for k in range(len(levels))])
        self.assertLessEqual(levels[-1]["instances"], 10000)
        # The level shown is the finest one whose frame, estimated from the coarsest's, fits 0.1 s.
        d = v["voxels"]
        estimate = [d["frame_without_voxels_ms"] + d["cube_us"] / 1000 * l["instances"] for l in levels]
        fitting = [k for k, e in enumerate(estimate) if e <= d["target_ms"]]
        self.assertEqual(d["level"], fitting[0] if fitting else len(levels) - 1)
        Select(browser.driver.find_element("id", "detail")).select_by_value("0")
        now = browser.run("return hullmapView.voxels")
        self.assertEqual((now["level"], now["instances"], now["merged"]), (0, levels[0]["instances"], False))
        self.assertEqual(browser.errors(), [])


if __name__ == "__main__":
    reason = headless_chromium.missing()
    if reason:
        print("SKIP: " + reason)
        sys.exit(77)
    unittest.main(verbosity=2)
