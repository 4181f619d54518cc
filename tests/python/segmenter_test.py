"""semfuse.Segmenter: what the callback receives, what becomes of what it returns (a good result
is fused, a raised exception or a malformed result costs that frame only and is counted), the
options (camera, every Nth frame, delay), and the interpreter's lock during blocking calls."""
from __future__ import annotations

import re
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np
import pytest

import semfuse
from conftest import BOX, CAMERA, DOMAIN, LOOPBACK_PROFILE, TABLE, reserve_another_domain, wait_for, wall_frame, wall_labels


def handled(segmenter: semfuse.Segmenter) -> int:
    """Frames the callback has finished with, well or not."""
    stats = segmenter.stats()
    return stats.segmented + stats.failed


def publish_in_step(camera: semfuse.CameraPublisher, segmenter: semfuse.Segmenter, seqs, server=None,
                    **frame) -> None:
    """Publishes the wall frames `seqs` one at a time, each once the segmenter (and the server, when
    given: its pose of the frame) is done with the last."""
    for seq in seqs:
        before = handled(segmenter)
        camera.publish(seq=seq, **{**wall_frame(seq), **frame})
        wait_for(lambda: handled(segmenter) > before, what=f"the segmenter to handle frame {seq}")
        if server is not None:
            wait_for(lambda: any(p.seq == seq for p in server.client.take_poses(0.1)), what=f"the pose of {seq}")


def test_the_callback_gets_the_frame_the_camera_published() -> None:
    seen: list[semfuse.Frame] = []
    arrays: list[tuple[np.ndarray, np.ndarray]] = []

    def segment(frame: semfuse.Frame):
        seen.append(frame)
        arrays.append((frame.depth.copy(), frame.color.copy()))
        return wall_labels(frame)

    camera = semfuse.CameraPublisher("wall", depth_encoding="float", color_encoding="raw", domain_id=DOMAIN)
    with semfuse.Segmenter(segment, segmenter_id="probe", domain_id=DOMAIN) as segmenter:
        assert camera.wait_for_reader(10)
        assert segmenter.wait_for_camera(10)
        publish_in_step(camera, segmenter, [3], stamp=1234.5, frame_id="wall_optical")
    (frame,) = seen
    published = wall_frame(3)
    assert (frame.camera_id, frame.seq, frame.frame_id) == ("wall", 3, "wall_optical")
    assert frame.stamp == pytest.approx(1234.5, abs=1e-6)
    assert frame.intrinsics == CAMERA
    depth, color = arrays[0]
    assert depth.dtype == np.float32 and depth.shape == (480, 640)
    np.testing.assert_array_equal(depth, published["depth"])
    assert color.dtype == np.uint8 and color.shape == (480, 640, 3)
    np.testing.assert_array_equal(color, published["color"])
    np.testing.assert_allclose(frame.pose, published["pose"], atol=1e-9)
    # The arrays stay valid after the callback returned (they own their images).
    assert frame.depth.shape == (480, 640) and float(frame.depth[10, 10]) == 2.0


def refuse():
    raise ValueError("no labels for this frame")


# What the callback returns for each frame seq; EXPECTED_ERRORS says what the segmenter must say
# about the bad ones.
def results(frame: semfuse.Frame):
    labels = wall_labels(frame)
    cases = {
        0: lambda: labels,
        1: refuse,
        2: lambda: np.zeros((481, 640), np.uint16),
        3: lambda: labels.astype(np.float32),
        4: lambda: None,
        5: lambda: np.full((480, 640), 70000, np.int32),
        6: lambda: (labels, np.ones((10, 10), np.float32)),
        7: lambda: (labels, np.full((480, 640), 1.5, np.float32)),
        8: lambda: (labels, np.full((480, 640), 0.75, np.float64)),
        9: lambda: (labels, None, None, None),
        10: lambda: labels[::2, ::2].astype(np.int64),  # half size, another integer type: fine
        11: lambda: (labels, None, np.ones((10, 10), np.uint16)),
        12: lambda: (labels, None, np.full(labels.shape, -1, np.int32)),
    }
    return cases[frame.seq]()


EXPECTED_ERRORS = {
    1: "ValueError: no labels for this frame",
    2: "labels of 481x640 (rows x cols) are larger than the frame's 480x640",
    3: "labels must be integers (uint16)",
    4: "the callback returned None",
    5: "labels range from 70000 to 70000, outside uint16",
    6: "confidence is a float32 array of shape (10, 10), the labels are 480x640",
    7: "outside [0, 1]",
    9: "a sequence of 4 items",
    11: "instances are 10x10 (rows x cols), the labels 480x640",
    12: "instances range from -1 to -1, outside uint16",
}


def test_a_callback_that_raises_or_returns_a_wrong_result_costs_that_frame_only(server) -> None:
    camera = semfuse.CameraPublisher("wall", domain_id=DOMAIN)
    assert camera.wait_for_server(10)
    errors: dict[int, str] = {}
    with semfuse.Segmenter(results, segmenter_id="flaky", domain_id=DOMAIN) as segmenter:
        assert segmenter.wait_for_camera(10)
        for seq in range(13):
            publish_in_step(camera, segmenter, [seq], server)
            if seq in EXPECTED_ERRORS:
                errors[seq] = segmenter.stats().last_error
        assert segmenter.wait_for_acknowledgements(10)
        stats = segmenter.stats()
        assert segmenter.running  # the run went on
    for seq, expected in EXPECTED_ERRORS.items():
        assert expected in errors[seq], f"frame {seq}: {errors[seq]!r}"
    assert stats.callback_errors == 1
    assert stats.invalid_results == len(EXPECTED_ERRORS) - 1
    assert stats.failed == len(EXPECTED_ERRORS)
    assert stats.segmented == stats.published == 13 - len(EXPECTED_ERRORS)

    # The server fused every frame and the three good results, and was sent nothing malformed.
    status = server.wait_until(lambda s: s.segmentations_integrated == 3 and s.frames_integrated == 13)
    assert status.rejected_count() == 0 and status.dropped_count() == 0
    sample = server.client.labels_at(np.array([[-0.5, 0.0, 2.0], [0.5, 0.0, 2.0]]))
    assert sample["observed"].all()
    assert sample["label"].tolist() == [TABLE, BOX]


def recorder(into: list, key):
    def segment(frame: semfuse.Frame):
        into.append(key(frame))
        return wall_labels(frame)
    return segment


def test_the_options_choose_the_frames_and_delay_the_results() -> None:
    # camera_id: the frames of that camera only.
    camera_a = semfuse.CameraPublisher("a", domain_id=DOMAIN)
    camera_b = semfuse.CameraPublisher("b", domain_id=DOMAIN)
    only_a: list[tuple[str, int]] = []
    with semfuse.Segmenter(recorder(only_a, lambda f: (f.camera_id, f.seq)), camera_id="a", domain_id=DOMAIN) as a:
        assert camera_a.wait_for_reader(10) and camera_b.wait_for_reader(10)
        for seq in range(4):
            for camera in (camera_a, camera_b):
                received = a.stats().received
                camera.publish(seq=seq, **wall_frame(seq))
                wait_for(lambda: a.stats().received > received, what="the frame")
        wait_for(lambda: handled(a) == 4, what="the segmenter")
    assert only_a == [("a", seq) for seq in range(4)]

    # every: every Nth frame received.
    every_third: list[int] = []
    a = None  # its reader leaves the topic
    with semfuse.Segmenter(recorder(every_third, lambda f: f.seq), every=3, domain_id=DOMAIN) as b:
        wait_for(lambda: camera_b.matched_readers == 1, what="the segmenter's reader")
        for seq in range(7):
            received = b.stats().received
            camera_b.publish(seq=seq, **wall_frame(seq))
            wait_for(lambda: b.stats().received > received, what="the frame")
        wait_for(lambda: handled(b) == 3, what="the segmenter")
        stats = b.stats()
    assert every_third == [0, 3, 6]
    assert (stats.received, stats.not_selected) == (7, 4)

    # delay: each result is held that long before it is published.
    b = None
    with semfuse.Segmenter(wall_labels, delay=0.6, domain_id=DOMAIN) as late:
        wait_for(lambda: camera_b.matched_readers == 1, what="the segmenter's reader")
        camera_b.publish(**wall_frame(0))
        wait_for(lambda: late.stats().segmented == 1, what="the late segmenter")
        segmented_at = time.monotonic()
        assert late.stats().published == 0
        wait_for(lambda: late.stats().published == 1, timeout=5, what="the delayed result")
        held = time.monotonic() - segmented_at
    assert 0.45 < held < 2.0


def test_stop_from_inside_the_callback_is_refused_and_counted() -> None:
    holder: list[semfuse.Segmenter] = []

    def segment(frame):
        holder[0].stop()

    camera = semfuse.CameraPublisher("self-stop", domain_id=DOMAIN)
    with semfuse.Segmenter(segment, domain_id=DOMAIN) as segmenter:
        holder.append(segmenter)
        assert camera.wait_for_reader(10)
        publish_in_step(camera, segmenter, [0])
        stats = segmenter.stats()
    assert stats.callback_errors == 1
    assert "would wait for itself" in stats.last_error


def counting_rate_while(call) -> float:
    """How fast another Python thread counts while `call` runs, per second. A call that keeps the
    interpreter's lock lets it run only between Python's 5 ms switch intervals, before and after."""
    count = 0
    running = True

    def counter():
        nonlocal count
        while running:
            count += 1

    thread = threading.Thread(target=counter)
    thread.start()
    time.sleep(0.05)
    start, started = count, time.monotonic()
    try:
        call()
    except semfuse.Error:
        pass
    done, elapsed = count, time.monotonic() - started
    running = False
    thread.join()
    return (done - start) / elapsed


def test_the_lock_test_tells_a_call_that_keeps_the_lock() -> None:
    # A regular expression that backtracks for a second in C, holding the lock all along.
    held = counting_rate_while(lambda: re.match(r"(a+)+$", "a" * 24 + "b"))
    free = counting_rate_while(lambda: time.sleep(0.5))
    assert held < 0.1 * free


_quiet: list[int] = []


def _quiet_domain() -> int:
    if not _quiet:
        _quiet.append(reserve_another_domain())
    return _quiet[0]


@pytest.mark.parametrize("name", ["take_poses", "raycast", "wait_for_status", "segmenter_run", "wait_for_server"])
def test_blocking_calls_let_other_python_threads_run(name: str) -> None:
    quiet = _quiet_domain()  # a domain no server of any test uses
    client = semfuse.MapClient(domain_id=quiet, timeout=0.6)
    segmenter = semfuse.Segmenter(wall_labels, domain_id=quiet)
    camera = semfuse.CameraPublisher("nobody", domain_id=quiet)
    calls = {
        "take_poses": lambda: client.take_poses(0.6),
        "raycast": lambda: client.raycast(np.eye(4), CAMERA),
        "wait_for_status": lambda: client.wait_for_status(),
        "segmenter_run": lambda: segmenter.run(duration=0.6),
        "wait_for_server": lambda: camera.wait_for_server(0.6),
    }
    free = counting_rate_while(lambda: time.sleep(0.3))
    assert counting_rate_while(calls[name]) > 0.3 * free
    segmenter.stop()


def test_a_segmenter_left_running_does_not_hold_the_interpreter_at_exit() -> None:
    script = textwrap.dedent(f"""
        import os, numpy as np
        os.environ["CYCLONEDDS_URI"] = "file://{LOOPBACK_PROFILE}"
        import semfuse
        def segment(frame):
            return np.ones(frame.depth.shape, np.uint16)
        segmenter = semfuse.Segmenter(segment, domain_id={DOMAIN})
        segmenter.start()
        camera = semfuse.CameraPublisher("exit", domain_id={DOMAIN})
        camera.wait_for_reader(10)
        depth = np.full((48, 64), 1.0, np.float32)
        k = semfuse.Intrinsics(64, 48, 50.0, 50.0, 31.5, 23.5)
        for seq in range(20):
            camera.publish(depth, k, seq=seq)
        print("published", flush=True)
    """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert "published" in done.stdout
