"""python_prototypes/temporal.py, the geometry chapter 29's checks lean on: a still
camera uncovers nothing; a step uncovers only what the boxes hid, beside them; with one
sample a pixel landing anywhere in it, the plane test keeps every tap on the same flat
surface where comparing depths turns some away; painting the boxes blue changes nothing
else; the page's figure is drawn."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import ROOT

from python_prototypes import scene_io, temporal

SCENE = ROOT / "assets" / "scenes" / "cornell_box.scene"
SIZE = 96


@pytest.fixture(scope="module")
def painted():
    return scene_io.parse_scene(temporal.painted_blue(SCENE.read_text()), SCENE)


def test_a_still_camera_uncovers_nothing(painted):
    assert not temporal.disoccluded(painted, painted.camera, painted.camera, SIZE).any()


def test_a_step_uncovers_only_what_the_boxes_hid(painted):
    """The uncovered pixels show the room (the back wall, the floor), but for a few of a
    box's faces that turn into view, and each lies within 3 pixels of one that shows a
    box."""
    now = temporal.moved(painted.camera, (0.1, 0.1, 0.0))
    uncovered = temporal.disoccluded(painted, painted.camera, now, SIZE)
    _, _, material = temporal.first_hits(painted, now, SIZE)
    names = list(painted.materials)
    assert 30 <= uncovered.sum() <= 300
    assert (material[uncovered] == names.index("blue")).mean() < 0.05
    box = material == names.index("blue")
    near = box.copy()
    for _ in range(3):
        near = near | np.roll(near, 1, 0) | np.roll(near, -1, 0) | np.roll(near, 1, 1) | \
            np.roll(near, -1, 1)
    assert near[uncovered].all()


@pytest.mark.parametrize("step", [(0.05, 0.0, 0.0), (0.1, 0.1, 0.0)])
def test_the_plane_keeps_what_depths_turn_away(painted, step):
    """Measured: depths within 2% keep 96%, within 1% 78%; the plane keeps all."""
    for tolerance in (0.02, 0.01):
        by_depth, by_plane = temporal.same_surface_rates(painted, painted.camera, step, SIZE,
                                                         tolerance)
        print(f"{step} within {tolerance}: depths keep {by_depth:.3f}, "
              f"the plane {by_plane:.3f}")
        assert by_plane > 0.999 and by_depth < 0.98


def test_painting_changes_only_the_boxes():
    text = SCENE.read_text()
    painted = temporal.painted_blue(text)
    assert painted.count(temporal.BLUE) == 1 and painted.count(" blue name ") == 12
    assert painted.replace(temporal.BLUE, "").replace(" blue name ", " white name ") == text
    assert all(" blue " in line for line in painted.splitlines() if line.endswith("_box"))


def test_the_figure_is_drawn(tmp_path):
    path = tmp_path / "temporal.png"
    temporal.main(["--figure", str(path)])
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
