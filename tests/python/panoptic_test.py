"""A panoptic Python segmenter: its callback returns (labels, confidence, instances), and the
server's objects follow the instances. On the wall scene (table left of x = 0, box right of it)
the box half is two instances, split at x = 0.6: the objects service answers two boxes there,
where the class-only segmenter of map_queries_test gets one."""
from __future__ import annotations

import numpy as np
import pytest

import semfuse
from conftest import BOX, DOMAIN, TABLE, Server, build_wall, wall_labels

SPLIT_X = 0.6


def panoptic(frame: semfuse.Frame):
    """The wall's labels, the table as instance 7 and the box as instances 1 and 2 (ids of this frame only)."""
    labels = wall_labels(frame)
    u = np.arange(frame.intrinsics.width, dtype=np.float64)
    x_world = (u - frame.intrinsics.cx) / frame.intrinsics.fx * frame.depth[0, :] + frame.pose[0, 3]
    row = np.where(x_world < 0.0, 7, np.where(x_world < SPLIT_X, 1 + frame.seq % 2, 2 - frame.seq % 2))
    instances = np.repeat(row[None, :], frame.intrinsics.height, axis=0).astype(np.int32)
    return labels, None, instances


@pytest.fixture(scope="module")
def panoptic_wall(tmp_path_factory):
    server = Server(tmp_path_factory.mktemp("panoptic"), "--legend", "synthetic", "--autosave-period", "0")
    build_wall(server, range(10), segment=panoptic)
    yield server
    assert server.stop() == 0, server.output()


def test_the_instances_a_python_callback_returns_make_the_objects(panoptic_wall) -> None:
    status = panoptic_wall.wait_until(lambda s: s.segmentations_integrated == 10 and s.pending_segmentations == 0)
    assert status.rejected_count() == 0 and status.dropped_count() == 0
    boxes = sorted(panoptic_wall.client.objects(label=BOX, min_voxels=100), key=lambda o: o.centroid[0])
    assert len(boxes) == 2, boxes
    assert boxes[0].bbox_max[0] < SPLIT_X + 0.05 and boxes[1].bbox_min[0] > SPLIT_X - 0.05
    assert abs(boxes[0].bbox_min[0]) < 0.05  # the first box begins where the table ends
    tables = panoptic_wall.client.objects(label=TABLE, min_voxels=100)
    assert len(tables) == 1
