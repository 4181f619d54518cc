"""semfuse.MapClient beyond the queries: the pose iterator and subscription, save / reset / load,
the errors of calls the server refuses or never answers, what the client refuses itself, and the
camera publisher's array forms. Each test has a server of its own."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import semfuse
from conftest import CAMERA, DOMAIN, TABLE, VOXEL, WALL_Z, build_wall, reserve_another_domain, wait_for, wall_frame


def test_pose_iterator_and_subscription(server, tmp_path: Path) -> None:
    client = semfuse.MapClient(domain_id=DOMAIN)
    build_wall(server, range(3))
    assert [p.seq for p in client.poses(idle_timeout=1.0)] == [0, 1, 2]

    seen: list[int] = []

    def on_pose(pose: semfuse.TrackedPose) -> None:
        seen.append(pose.seq)
        if pose.seq == 4:
            raise RuntimeError("the callback failed on purpose")

    with client.subscribe_poses(on_pose) as subscription:
        with pytest.raises(RuntimeError, match="subscription"):
            client.take_poses()
        build_wall(server, range(3, 6))
        wait_for(lambda: len(seen) == 3, what="the subscription's poses")
    assert seen == [3, 4, 5]
    assert (subscription.delivered, subscription.callback_errors) == (2, 1)
    assert "RuntimeError: the callback failed on purpose" in subscription.last_error
    assert subscription.closed
    build_wall(server, range(6, 7))
    assert [p.seq for p in client.take_poses(timeout=2.0)] == [6]


def test_save_reset_and_load(server, tmp_path: Path) -> None:
    client = server.client
    build_wall(server, range(2))
    point = np.array([[-0.5, 0.0, WALL_Z]])
    saved = client.save(str(tmp_path / "saved.vdb"))
    assert saved.last_save_ok and (tmp_path / "saved.vdb").stat().st_size > 0
    assert client.reset().allocated_voxels == 0
    assert not client.labels_at(point)["observed"][0]
    assert client.load(str(tmp_path / "saved.vdb")).allocated_voxels > 0
    assert client.labels_at(point)["label"].tolist() == [TABLE]


def test_refusals_are_server_errors_with_a_reason(server) -> None:
    client = server.client
    big = semfuse.Intrinsics(4000, 3000, 2000.0, 2000.0, 1999.5, 1499.5)
    with pytest.raises(semfuse.ServerError) as refused:
        client.raycast(np.eye(4), big)
    assert (refused.value.reason, refused.value.status) == ("too_large", 5)
    assert "raycast of 4000x3000 exceeds the limit" in str(refused.value)

    with pytest.raises(semfuse.ServerError) as refused:
        client.region([1, 1, 1], [0, 0, 0])
    assert (refused.value.reason, refused.value.status) == ("invalid_argument", 1)
    assert "box max must be >= min" in str(refused.value)

    with pytest.raises(semfuse.ServerError, match="not in the legend") as refused:
        client.objects(label=999)
    assert refused.value.reason == "invalid_argument"

    with pytest.raises(semfuse.ServerError) as refused:
        client.load("/no/such/map.vdb")
    assert refused.value.reason in ("not_found", "invalid_argument")
    assert isinstance(refused.value, semfuse.Error) and not isinstance(refused.value, TimeoutError)


def test_what_the_client_refuses_never_leaves_it(server) -> None:
    client = server.client
    with pytest.raises(ValueError, match="pose: "):
        client.raycast(np.diag([1.0, 2.0, 1.0, 1.0]), CAMERA)  # not a rotation
    with pytest.raises(ValueError, match="4x4"):
        client.raycast(np.eye(3), CAMERA)
    with pytest.raises(ValueError, match="unknown raycast layer 'colour'"):
        client.raycast(np.eye(4), CAMERA, layers=["colour"])
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        client.labels_at(np.zeros((4, 2)))
    with pytest.raises(ValueError, match="not finite"):
        client.labels_at([[0.0, np.nan, 1.0]])
    with pytest.raises(ValueError, match="both"):
        client.mesh(box_min=[0, 0, 0])
    camera = semfuse.CameraPublisher("bad", domain_id=DOMAIN)
    frame = wall_frame(0)
    with pytest.raises(ValueError, match="the intrinsics say 480x640"):
        camera.publish(frame["depth"][:, :320], CAMERA)
    with pytest.raises(ValueError, match=r"\(rows, cols, 3\) uint8"):
        camera.publish(frame["depth"], CAMERA, color=frame["color"].astype(np.float32))
    with pytest.raises(ValueError, match="float metres or uint16 millimetres"):
        camera.publish(frame["depth"].astype(np.int32), CAMERA)
    with pytest.raises(ValueError, match="pose: "):
        camera.publish(frame["depth"], CAMERA, pose=np.diag([1.0, 1.0, -1.0, 1.0]))  # a reflection
    assert client.status().frames_received == 0


def test_uint16_millimetres_and_bgr_views_are_taken_as_given(server) -> None:
    camera = semfuse.CameraPublisher("mm", depth_encoding="png", color_encoding="png", domain_id=DOMAIN)
    assert camera.wait_for_server(10)
    frame = wall_frame(0)
    depth_mm = np.full((480, 640), 2000, np.uint16)
    bgr = frame["color"][..., ::-1].copy()
    camera.publish(depth_mm, CAMERA, color=bgr[..., ::-1], pose=frame["pose"])  # a strided RGB view
    server.wait_until(lambda s: s.frames_integrated == 1)
    view = server.client.raycast(frame["pose"], CAMERA, layers=["depth", "color"])
    assert abs(float(view["depth"][240, 320]) - 2.0) < VOXEL
    assert int(view["color"][240, 320, 0]) == 200


def test_a_call_nobody_answers_is_a_timeout_error() -> None:
    # A domain of its own: one picked by arithmetic was once another test's, whose server answered.
    nobody = semfuse.MapClient(domain_id=reserve_another_domain(), timeout=0.3)
    with pytest.raises(TimeoutError) as late:
        nobody.status()
    assert isinstance(late.value, semfuse.CallTimeout) and late.value.reason == "unavailable"
    assert "no server" in str(late.value)
    with pytest.raises(semfuse.CallTimeout):
        nobody.legend()
    assert nobody.take_poses(0.1) == [] and nobody.latest_status() is None
    assert list(nobody.poses(idle_timeout=0.2)) == []
