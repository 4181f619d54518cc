"""The examples run as their docstrings say: raycast_labels.py saves the label image of a known map,
dnn_segmenter.py labels real 7-Scenes frames with the ADE20K network and the server fuses them."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest

from conftest import (BOX, CAMERA, DOMAIN, LOOPBACK_PROFILE, SOURCE_DIR, TABLE, Process, Server, build_wall,
                      program, wait_for, wall_pose)

EXAMPLES = SOURCE_DIR / "client/python/examples"
DDS = ["--domain-id", str(DOMAIN), "--dds-profile", str(LOOPBACK_PROFILE)]


def shared_folder() -> Path:
    shared = Path(os.environ.get("SEMFUSE_SHARED", SOURCE_DIR.parent / "shared"))
    if not (shared / "models").is_dir() or not (shared / "data/7scenes-redkitchen").is_dir():
        if os.environ.get("CI") == "true":
            pytest.fail(f"the shared data is missing at {shared}")
        pytest.skip(f"no shared data at {shared} (set SEMFUSE_SHARED)")
    return shared


def test_raycast_labels_saves_the_label_image_of_the_map(server: Server, tmp_path: Path) -> None:
    build_wall(server, range(4))
    pose = wall_pose(5)
    k = [str(v) for v in (CAMERA.width, CAMERA.height, CAMERA.fx, CAMERA.fy, CAMERA.cx, CAMERA.cy)]
    done = subprocess.run([sys.executable, str(EXAMPLES / "raycast_labels.py"), *DDS, "--out", str(tmp_path / "view"),
                           "--pose", *[str(v) for v in pose[:3].ravel()], "--intrinsics", *k],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    legend = server.client.legend()
    image = cv2.cvtColor(cv2.imread(str(tmp_path / "view/labels.png")), cv2.COLOR_BGR2RGB)
    assert image.shape == (480, 640, 3)
    assert tuple(image[240, 100]) == legend.color_of(TABLE) and tuple(image[240, 540]) == legend.color_of(BOX)
    raw = cv2.imread(str(tmp_path / "view/labels_raw.png"), cv2.IMREAD_UNCHANGED)
    assert raw.dtype == np.uint16 and (raw[240, 100], raw[240, 540]) == (TABLE, BOX)
    assert "table:" in done.stdout and "box:" in done.stdout, done.stdout


def test_dnn_segmenter_labels_real_frames_that_the_server_fuses(tmp_path: Path) -> None:
    shared = shared_folder()
    server = Server(tmp_path, "--legend", "ade20k", "--autosave-period", "0")
    try:
        segmenter = Process([sys.executable, str(EXAMPLES / "dnn_segmenter.py"), *DDS, "--model",
                             str(shared / "models/ade20k_deeplabv3_mnv2_257_logits.pb"), "--idle-exit", "4"],
                            tmp_path / "segmenter.log")
        # The camera starts once the example listens (importing OpenCV and loading the network take a while).
        wait_for(lambda: "Ctrl-C stops" in segmenter.output() or segmenter.popen.poll() is not None, timeout=60,
                 what="the example to start")
        camera = Process([program("SEMFUSE_CAMERA_EXE"), *DDS, "--source",
                          f"7scenes:{shared / 'data/7scenes-redkitchen'}", "--last", "9", "--rate", "1",
                          "--log-level", "warn"], tmp_path / "camera.log")
        assert camera.wait(120) == 0, camera.output()
        assert segmenter.wait(120) == 0, segmenter.output()
        status = server.wait_until(lambda s: s.pending_segmentations == 0 and s.segmentations_integrated > 0)
        assert "segmentations published" in segmenter.output()
        assert status.frames_integrated == 10
        assert status.segmentations_integrated >= 5  # ~0.4 s a frame (more on a loaded machine) against 1 s
        assert status.rejected_count() == 0, status.rejected
        # The kitchen's wall (ADE20K 1) and floor (4) are in the map.
        objects = {o.label for o in server.client.objects(min_voxels=200)}
        assert {1, 4} <= objects, objects
    finally:
        assert server.stop() == 0, server.output()
