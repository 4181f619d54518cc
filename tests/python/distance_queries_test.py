"""semfuse.MapClient's distance-field queries against a map of known geometry: a wall 2 m in front
of a camera that slid along x (world z is the camera's forward axis), labeled table (4) left of
x = 0 and box (6) right of it, fused by a server with --esdf. Distances are checked against the
wall's analytic ones, within two of the field's voxels (4 cm on the default 1 cm map)."""
from __future__ import annotations

import numpy as np
import pytest

import semfuse
from conftest import BOX, DOMAIN, TABLE, WALL_Z, Server, build_wall

FIELD_VOXEL = 0.04
TOLERANCE = 2 * FIELD_VOXEL


def field_answers(client: semfuse.MapClient) -> list[np.ndarray]:
    """What the field says in front of both labeled halves: distances and the nearest table and box."""
    points = np.array([[-0.3, 0.0, 1.5], [0.0, 0.0, 1.5], [0.3, 0.0, 1.5]])
    plain = client.distances(points)
    table = client.semantic_distances([TABLE], points)
    box = client.semantic_distances([BOX], points)
    return [plain["known"], plain["distance"], table["found"], table["distance"], box["found"], box["distance"]]


@pytest.fixture(scope="module")
def wall(tmp_path_factory):
    """A client of a server with a distance field over the wall map, once the field has caught up.

    The field follows the map on a thread of its own: the status says when it has applied every
    change (its revision equals the map's) after the last frame's labels are in."""
    server = Server(tmp_path_factory.mktemp("wall"), "--legend", "synthetic", "--autosave-period", "0", "--esdf")
    build_wall(server, range(10))
    status = server.wait_until(
        lambda s: s.queued_frames == 0
        and s.pending_segmentations == 0
        and s.map_revision > 0
        and s.distance_field_revision == s.map_revision,
        timeout=60,
    )
    assert status.segmentations_integrated == 10
    client = semfuse.MapClient(domain_id=DOMAIN)
    answers = field_answers(client)
    assert answers[0].all() and answers[2].all() and answers[4].all(), answers
    yield client
    assert server.stop() == 0, server.output()


def test_distances_and_gradients_in_front_of_the_wall(wall) -> None:
    points = np.array([[0.0, 0.0, 1.5], [0.3, 0.2, 1.0], [-0.4, -0.1, 1.8], [0.0, 0.0, WALL_Z + 0.6]])
    samples = wall.distances(points)
    assert sorted(samples) == ["beyond", "distance", "gradient", "known"]
    assert samples["known"].dtype == np.bool_ and samples["known"].shape == (4,)
    assert samples["distance"].dtype == np.float32
    assert samples["gradient"].shape == (4, 3) and samples["gradient"].dtype == np.float32
    np.testing.assert_array_equal(samples["known"], [True, True, True, False])  # behind the wall: unseen
    assert not samples["beyond"][:3].any()
    np.testing.assert_allclose(samples["distance"][:3], WALL_Z - points[:3, 2], atol=TOLERANCE)
    for gradient in samples["gradient"][:3]:
        assert gradient @ np.array([0.0, 0.0, -1.0]) > 0.95  # away from the wall


def test_distances_refuse_points_that_are_not_n_by_3(wall) -> None:
    with pytest.raises(ValueError, match="points"):
        wall.distances(np.zeros((4, 2)))


def test_occupancy_slices_are_free_before_the_wall_and_occupied_at_it(wall) -> None:
    box = dict(bounds_min=[-0.5, -0.4], bounds_max=[0.5, 0.4])
    free = wall.occupancy_slice(z_min=1.5, z_max=1.8, **box)
    assert sorted(free) == ["cells", "frame_id", "origin", "resolution", "z"]
    assert free["cells"].dtype == np.int8 and free["cells"].ndim == 2
    assert free["resolution"] == pytest.approx(FIELD_VOXEL)
    height, width = free["cells"].shape
    assert width == pytest.approx(1.0 / FIELD_VOXEL, abs=2) and height == pytest.approx(0.8 / FIELD_VOXEL, abs=2)
    assert free["origin"][0] == pytest.approx(-0.5, abs=FIELD_VOXEL)
    assert free["z"] == pytest.approx(1.65)
    assert (free["cells"] == 0).mean() > 0.95
    at_wall = wall.occupancy_slice(z_min=WALL_Z - 0.03, z_max=WALL_Z + 0.03, **box)
    assert (at_wall["cells"] == 100).mean() > 0.95
    with pytest.raises(ValueError, match="bounds_min and bounds_max"):
        wall.occupancy_slice(bounds_min=[0.0, 0.0])


def test_semantic_distances_find_the_nearest_surface_of_a_label(wall) -> None:
    points = np.array([[-0.3, 0.0, 1.5], [0.3, 0.0, 1.5]])
    table = wall.semantic_distances([TABLE], points)
    assert sorted(table) == ["direction", "distance", "found", "label", "surface_point"]
    assert table["found"].all()
    np.testing.assert_array_equal(table["label"], [TABLE, TABLE])
    # Straight ahead for the point over the table; to the labels' border at x = 0 for the other.
    np.testing.assert_allclose(table["distance"], [0.5, np.hypot(0.3, 0.5)], atol=TOLERANCE)
    assert table["direction"][0] @ np.array([0.0, 0.0, 1.0]) > 0.95
    assert table["surface_point"][1][0] == pytest.approx(0.0, abs=TOLERANCE)
    both = wall.semantic_distances([TABLE, BOX], points)
    np.testing.assert_array_equal(both["label"], [TABLE, BOX])
    np.testing.assert_allclose(both["distance"], [0.5, 0.5], atol=TOLERANCE)


def test_a_semantic_slice_is_that_distance_over_a_plane(wall) -> None:
    grid = wall.semantic_slice([BOX], z=1.5, bounds_min=[-0.5, -0.3], bounds_max=[0.5, 0.3], resolution=0.05)
    distance = grid["distance"]
    assert distance.dtype == np.float32 and distance.shape == (12, 20)
    x = grid["min"][0] + (np.arange(20) + 0.5) * grid["resolution"]
    row = distance[6]  # y about 0
    expected = np.where(x >= 0.0, 0.5, np.hypot(x, 0.5))
    np.testing.assert_allclose(row, expected, atol=TOLERANCE)


def test_swept_spheres_stop_at_the_wall(wall) -> None:
    starts = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]])
    ends = np.array([[0.0, 0.0, 1.5], [0.0, 0.0, 2.5]])
    checks = wall.check_segments(starts, ends, radius=0.1)
    assert sorted(checks) == ["blocked_at", "fraction", "min_clearance", "status"]
    np.testing.assert_array_equal(checks["status"], [0, 1])  # free, collision
    assert checks["fraction"][0] == 1.0
    # The sphere touches the wall when its centre is 0.1 m before it: 0.9 m of 1.5 m.
    assert checks["fraction"][1] == pytest.approx(0.6, abs=TOLERANCE / 1.5)
    assert checks["blocked_at"][1][2] == pytest.approx(WALL_Z - 0.1, abs=TOLERANCE)
    assert checks["min_clearance"][0] == pytest.approx(0.4, abs=TOLERANCE)
    with pytest.raises(ValueError, match="as many points"):
        wall.check_segments(starts, ends[:1])
