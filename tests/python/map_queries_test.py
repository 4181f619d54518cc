"""semfuse.MapClient's queries against a map of known content: a wall 2 m in front of a camera that
slid along x, fused from 10 frames with poses, labeled table (4) left of x = 0 and box (6) right of
it by a Python segmenter. Every query's arrays are checked for shape, type and values."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import semfuse
from conftest import BOX, CAMERA, DOMAIN, TABLE, VOXEL, WALL_Z, Server, build_wall, wall_pose

FRAMES = 10


@pytest.fixture(scope="module")
def wall(tmp_path_factory):
    """(server, client): the wall map; the client listened to the poses from before the first frame."""
    server = Server(tmp_path_factory.mktemp("wall"), "--legend", "synthetic", "--autosave-period", "0")
    client = semfuse.MapClient(domain_id=DOMAIN)
    build_wall(server, range(FRAMES))
    yield server, client
    assert server.stop() == 0, server.output()


def test_a_raycast_gives_every_layer_as_arrays(wall) -> None:
    _, client = wall
    view = client.raycast(wall_pose(5), CAMERA)
    assert sorted(view) == ["color", "confidence", "depth", "labels", "normals"]
    shapes = {name: (a.shape, a.dtype) for name, a in view.items()}
    assert shapes == {"depth": ((480, 640), np.float32), "normals": ((480, 640, 3), np.float32),
                      "labels": ((480, 640), np.uint16), "confidence": ((480, 640), np.float32),
                      "color": ((480, 640, 3), np.uint8)}
    # From the pose of frame 5 (x = 0): the wall at 2 m, facing the camera, table left, box right.
    centre = view["depth"][200:280, 200:440]
    assert np.abs(centre - WALL_Z).max() < VOXEL
    np.testing.assert_allclose(view["normals"][240, 320], [0.0, 0.0, -1.0], atol=0.05)
    assert (view["labels"][100:380, 20:300] == TABLE).all()
    assert (view["labels"][100:380, 340:620] == BOX).all()
    assert (view["confidence"][100:380, 20:620] > 0).all()
    assert abs(int(view["color"][240, 320, 0]) - 200) <= 2  # the red every frame had

    only = client.raycast(wall_pose(5), CAMERA, layers=["depth", "labels"])
    assert sorted(only) == ["depth", "labels"]
    assert sorted(client.raycast(wall_pose(5), CAMERA, layers=semfuse.NORMALS | semfuse.COLOR)) == ["color", "normals"]
    np.testing.assert_array_equal(only["labels"], view["labels"])
    # Half the resolution: the same view.
    small = client.raycast(wall_pose(5), CAMERA.scaled(0.5), layers="labels")["labels"]
    assert small.shape == (240, 320)
    np.testing.assert_array_equal(small[50:190, 10:150], TABLE)


def test_labels_at_gives_the_voxels_at_points(wall) -> None:
    _, client = wall
    samples = client.labels_at(np.array([[-0.5, 0.1, WALL_Z], [0.5, -0.1, WALL_Z], [0.0, 0.0, 5.0]]))
    assert sorted(samples) == ["confidence", "label", "observed", "tsdf", "weight"]
    assert samples["observed"].tolist() == [True, True, False]
    assert samples["label"].tolist() == [TABLE, BOX, 0]
    assert samples["label"].dtype == np.uint16
    assert np.abs(samples["tsdf"][:2]).max() < VOXEL
    assert (samples["weight"][:2] > 0).all() and samples["weight"][2] == 0
    assert (samples["confidence"][:2] > 0).all()
    # One point as a plain list works too.
    assert client.labels_at([-0.5, 0.1, WALL_Z])["label"].tolist() == [TABLE]


def test_region_summarises_a_box(wall) -> None:
    _, client = wall
    # 0.6 m x 0.8 m of the wall, all table.
    region = client.region([-0.7, -0.4, WALL_Z - 0.05], [-0.1, 0.4, WALL_Z + 0.05])
    assert [a.label for a in region.histogram] == [TABLE]
    assert region.histogram[0].area_m2 == pytest.approx(0.6 * 0.8, rel=0.1)
    assert region.observed_voxels > 0 and region.occupied_voxels > 0


def test_objects_are_the_two_labeled_halves(wall) -> None:
    _, client = wall
    objects = client.objects(min_voxels=100)
    by_label = {o.label: o for o in objects}
    assert set(by_label) == {TABLE, BOX}
    table, box = by_label[TABLE], by_label[BOX]
    assert table.bbox_max[0] < 0.05 and box.bbox_min[0] > -0.05
    assert table.centroid[2] == pytest.approx(WALL_Z, abs=0.02)
    assert table.centroid.shape == (3,) and table.bbox_min.dtype == np.float64
    assert [o.label for o in client.objects(label=BOX, min_voxels=100)] == [BOX]
    # The table half's surface, as the region query measures it.
    surface = client.region(table.bbox_min - VOXEL, table.bbox_max + VOXEL).histogram
    assert table.area_m2 == pytest.approx(next(a.area_m2 for a in surface if a.label == TABLE), rel=0.1)
    # A flat rectangle on axis-aligned edges: its oriented box is its bounding box.
    rotation = table.box_rotation
    assert rotation.shape == (3, 3)
    np.testing.assert_allclose(rotation @ rotation.T, np.eye(3), atol=1e-6)
    assert np.linalg.det(rotation) == pytest.approx(1.0, abs=1e-6)
    np.testing.assert_allclose(table.box_center, (table.bbox_min + table.bbox_max) / 2, atol=2 * VOXEL)
    np.testing.assert_allclose(sorted(table.box_half_extents), sorted((table.bbox_max - table.bbox_min) / 2),
                               atol=2 * VOXEL)
    assert not table.fragment and not box.fragment
    # Every frame of the slide saw both halves whole.
    for half in (table, box):
        assert half.frame_count == FRAMES
        assert sorted(half.frames) == [("wall", seq) for seq in range(FRAMES)]
    # Filters: near a point of the box half, and with the fragments.
    near_box = client.objects(near=[0.5, 0.0, WALL_Z], radius=0.1)
    assert [o.label for o in near_box] == [BOX]
    with_fragments = client.objects(include_fragments=True)
    assert {o.id for o in objects} <= {o.id for o in with_fragments}
    whole = {o.id for o in client.objects()}
    assert all(o.fragment for o in with_fragments if o.id not in whole)
    with pytest.raises(ValueError, match="radius"):
        client.objects(near=[0.0, 0.0, WALL_Z])
    # The map no longer changes: what a minute-old grouping will do is the same two halves.
    recent = client.objects(max_age=60.0)
    assert sorted((o.id, o.label) for o in recent) == sorted((o.id, o.label) for o in client.objects())
    with pytest.raises(ValueError, match="max_age"):
        client.objects(max_age=-1.0)


def test_object_events_tell_which_objects_appeared(wall) -> None:
    _, client = wall
    ids = {o.id: o.label for o in client.objects(min_voxels=100)}
    appeared: dict[int, int] = {}
    for update in client.take_object_events(timeout=5.0):
        assert update.update >= 1 and update.stamp > 0
        for event in update.events:
            assert event.kind in ("appeared", "merged", "split", "vanished")
            if event.kind == "appeared":
                appeared[event.id] = event.label
    assert {i: appeared.get(i) for i in ids} == ids
    assert client.rejected_object_events == 0
    # Nothing changed since: no new update.
    assert client.take_object_events(timeout=0.0) == []


def test_the_mesh_comes_as_arrays_and_as_ply(wall, tmp_path: Path) -> None:
    _, client = wall
    legend = client.legend()
    mesh = client.mesh()
    n = mesh.vertices.shape[0]
    assert n > 1000
    assert (mesh.vertices.dtype, mesh.faces.dtype, mesh.labels.dtype, mesh.colors.dtype) == (
        np.float32, np.uint32, np.uint16, np.uint8)
    assert mesh.faces.shape[1] == 3 and mesh.normals.shape == (n, 3) and mesh.scores.shape == (n,)
    assert mesh.faces.max() < n
    assert np.abs(mesh.vertices[:, 2] - WALL_Z).max() < 2 * VOXEL
    assert set(np.unique(mesh.labels).tolist()) == {TABLE, BOX}
    left = mesh.vertices[:, 0] < -0.05
    assert (mesh.labels[left] == TABLE).all()
    for label in (TABLE, BOX):
        np.testing.assert_array_equal(mesh.colors[mesh.labels == label], [legend.color_of(label)] * int((mesh.labels == label).sum()))
    assert mesh.ply.startswith(b"ply\nformat binary_little_endian 1.0\n")
    mesh.save(str(tmp_path / "wall.ply"))
    assert (tmp_path / "wall.ply").read_bytes() == mesh.ply

    part = client.mesh([-0.5, -0.3, 1.9], [-0.1, 0.3, 2.1])
    assert 0 < part.vertices.shape[0] < n
    assert part.vertices[:, 0].max() <= -0.1 + VOXEL and part.vertices[:, 0].min() >= -0.5 - VOXEL
    assert set(np.unique(part.labels).tolist()) == {TABLE}


def test_status_legend_and_poses(wall) -> None:
    server, client = wall
    status = client.status()
    assert (status.frames_integrated, status.segmentations_integrated) == (FRAMES, FRAMES)
    assert [c.camera_id for c in status.cameras] == ["wall"]
    assert status.cameras[0].tracking_state == "given"
    assert status.voxel_size == pytest.approx(VOXEL)
    assert status.rejected_count() == 0
    stages = {t.stage: t for t in status.stages}
    assert stages["integrate"].count == FRAMES and stages["frame_decode"].count == FRAMES
    assert 0 < stages["integrate"].p50_ms <= stages["integrate"].p95_ms <= stages["integrate"].max_ms
    assert client.wait_for_status().frames_integrated >= 0

    legend = client.legend()
    assert legend.name == "synthetic"
    assert (legend.name_of(TABLE), legend.id_of("box"), legend.name_of(999)) == ("table", BOX, None)
    assert TABLE in legend and legend.is_background(0)
    image = legend.colorize(np.array([[TABLE, BOX]], np.uint16))
    assert image.shape == (1, 2, 3) and tuple(image[0, 0]) == legend.color_of(TABLE)

    # The client listened from before the first frame: every pose, as given.
    poses = client.take_poses(timeout=2.0)
    assert [p.seq for p in poses] == list(range(FRAMES))
    for p in poses:
        assert (p.camera_id, p.state, p.posed) == ("wall", "given", True)
        np.testing.assert_allclose(p.pose, wall_pose(p.seq), atol=1e-9)
    assert client.rejected_poses == 0


