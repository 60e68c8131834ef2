"""A generated street (issue 30): hullmap.build finds its ground, Map.surfaces gives it as a height
field, and Map.check hits it as `hullmap check` does."""
import numpy as np
import pytest

import hullmap
from conftest import fresh_dir, run_cli


@pytest.fixture(scope="module")
def street():
    scene = fresh_dir("street_scene")
    run_cli("generate", "--layout", "outdoor", "--track-length", "80", "--track-width", "40", "--buildings", "4",
            "--trees", "4", "--cars", "3", "--posts", "3", "--keyframes", "40", "--density", "1", "-o", scene)
    return scene


def test_the_ground_is_a_height_field_that_checks_hit(street):
    built = hullmap.build(str(street / "map_points.txt"), trajectory=str(street / "KeyFrameTrajectory.txt"),
                          align=str(street / "reference_trajectory.txt"))
    assert built.report["ground"] is not None
    [ground] = built.surfaces
    assert ground.name == "ground" and ground.normal is None and ground.offset is None
    field = ground.field
    grid = built.report["ground"]["grid"]
    assert field.heights.shape == (grid["ny"], grid["nx"])
    assert field.step == grid["step"] and list(field.origin) == grid["origin"]
    # Straight down through the middle node of the field: it collides with the ground.
    j, i = grid["ny"] // 2, grid["nx"] // 2
    x, y = field.origin + field.step * (np.array([i, j]) + 0.5)
    top = field.heights[j, i]
    rows = built.check(np.array([[x, y, top + 20.0, x, y, top - 5.0]]), radius=0.3)
    assert rows["collides"][0] and rows["surface"][0] == "ground"
    # The same as the CLI on the saved directory.
    out = fresh_dir("street_py")
    built.save(out)
    loaded = hullmap.load(out)
    assert loaded.surfaces[0].field.heights.tolist() == field.heights.tolist()
    again = loaded.check(np.array([[x, y, top + 20.0, x, y, top - 5.0]]), radius=0.3)
    assert again["t"][0] == rows["t"][0]


def test_the_streets_scale_drift_is_undone_unless_one_similarity_is_asked(street):
    inputs = dict(trajectory=str(street / "KeyFrameTrajectory.txt"), align=str(street / "reference_trajectory.txt"))
    drift = hullmap.build(str(street / "map_points.txt"), **inputs)
    fit = drift.report["alignment"]
    assert fit["model"] == "drift" and fit["rmse"] < 0.1 * fit["similarity_rmse"]
    assert drift.report["input_to_output"]["exact"] is False
    one = hullmap.build(str(street / "map_points.txt"), align_model="similarity", **inputs)
    assert one.report["alignment"]["model"] == "similarity" and one.report["input_to_output"]["exact"] is True
    assert one.report["alignment"]["rmse"] == pytest.approx(fit["similarity_rmse"])
    with pytest.raises(ValueError, match="align_model: expected 'auto', 'similarity' or 'drift'"):
        hullmap.build(str(street / "map_points.txt"), align_model="piecewise", **inputs)
