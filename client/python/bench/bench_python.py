#!/usr/bin/env python3
"""bench_python: what the Python package costs over the C++ client library, both measured in this run.

1. Segmenter: 640x480 frames (raw depth and colour) go one at a time from a CameraPublisher to a
   segmenter in the same process, whose labelling function is the same trivial one in both
   languages: "constant" (one label image made once, returned for every frame: the cost of the call
   alone) and "near/far" (1 nearer than 1.5 m, 2 beyond, 0 without depth, made for each frame). The Segmenter times the function as it calls it: for
   Python that is taking the interpreter's lock, the frame's images as numpy arrays, the call, the
   labels checked and copied back. Also timed: publishing a frame until its result is published.
   The segmenters take turns, in rounds.
2. Raycast: a 640x480 raycast of every layer from semfuse.MapClient (timed in Python, to the dict
   of arrays) and from the C++ client::MapClient (timed in C++), in turns, against one
   semfuse-server holding the synthetic room (120 frames, 1 cm voxels).

    python3 client/python/bench/bench_python.py --build-dir build/release
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
PROFILE = ROOT / "deploy/dds/localhost.xml"

# The demo's two overviews of the synthetic room and two views across it (camera-to-world, 3x4 rows).
VIEWS = [
    [0.6114475, 0.4127809, -0.6750881, 2.2, 0.7912850, -0.3189671, 0.5216590, -1.7, 0, -0.8531541, -0.5216590, 2.2],
    [-0.6050833, -0.2842128, 0.7437051, -2.2, -0.7961622, 0.2160017, -0.5652159, 1.6, 0, -0.9341126, -0.3569785, 1.8],
    [1, 0, 0, 0, 0, 0, 1, -1.8, 0, -1, 0, 1.3],
    [-1, 0, 0, 0, 0, 0, -1, 1.8, 0, -1, 0, 1.3],
]


def parse() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    parser.add_argument("--build-dir", type=Path, default=ROOT / "build/release")
    parser.add_argument("--frames", type=int, default=60, help="frames per segmenter and round")
    parser.add_argument("--rounds", type=int, default=4, help="turns of each segmenter")
    parser.add_argument("--raycasts", type=int, default=60, help="raycasts of each client")
    parser.add_argument("--domain-id", type=int, default=30 + os.getpid() % 190)
    return parser.parse_args()


args = parse()
os.environ["CYCLONEDDS_URI"] = f"file://{PROFILE}"  # before the first participant
sys.path[:0] = [str(args.build_dir / "client/python"), str(args.build_dir / "client/python/bench")]
import numpy as np  # noqa: E402

import semfuse  # noqa: E402
import _semfuse_bench  # noqa: E402

CAMERA = semfuse.Intrinsics(640, 480, 525.0, 525.0, 319.5, 239.5)


CONSTANT = np.ones((480, 640), np.uint16)


def constant(frame: semfuse.Frame) -> np.ndarray:
    return CONSTANT


def near_and_far(frame: semfuse.Frame) -> np.ndarray:
    labels = np.full(frame.depth.shape, 2, np.uint16)
    labels[frame.depth < 1.5] = 1
    labels[frame.depth <= 0.0] = 0
    return labels


def test_frame() -> dict:
    rows, cols = np.mgrid[0:480, 0:640]
    depth = (0.5 + 2.5 * cols / 640 + 0.2 * np.sin(rows / 30)).astype(np.float32)
    depth[::7, ::5] = 0.0
    color = np.random.default_rng(1).integers(0, 255, (480, 640, 3), dtype=np.uint8)
    return {"depth": depth, "color": color, "intrinsics": CAMERA, "pose": np.eye(4)}


FUNCTIONS = {"constant": constant, "near_far": near_and_far}
KINDS = [(language, function) for function in FUNCTIONS for language in ("cpp", "python")]


class TimedSegmenter:
    """A Python or a C++ segmenter, and what the bench reads off it: results published, and the
    Segmenter's time of the last call of the labelling function."""

    def __init__(self, language: str, function: str, domain: int) -> None:
        self.language = language
        if language == "python":
            self.python = semfuse.Segmenter(FUNCTIONS[function], segmenter_id=f"bench-python-{function}",
                                            domain_id=domain)
        else:
            self.cpp = _semfuse_bench.CppSegmenter(domain, function)

    def start(self) -> None:
        (self.python if self.language == "python" else self.cpp).start()

    def stop(self) -> None:
        (self.python if self.language == "python" else self.cpp).stop()

    def published_and_last_ms(self) -> tuple[int, float]:
        if self.language == "python":
            stats = self.python.stats()
            return stats.published, stats.last_segment_ms
        counts = self.cpp.stats()
        return counts["published"], counts["last_segment_ms"]


def bench_segmenters(domain: int) -> dict[tuple[str, str], dict[str, list[float]]]:
    camera = semfuse.CameraPublisher("bench", depth_encoding="raw", color_encoding="raw", domain_id=domain)
    segmenters = {kind: TimedSegmenter(*kind, domain) for kind in KINDS}
    frame = test_frame()
    results: dict[tuple[str, str], dict[str, list[float]]] = {kind: {"function": [], "round_trip": []} for kind in KINDS}
    if not camera.wait_for_reader(10):
        sys.exit("bench_python: the segmenters' readers were not matched")
    seq = 0
    for round_ in range(args.rounds):
        for kind in KINDS:
            segmenter = segmenters[kind]
            stats = segmenter.published_and_last_ms
            segmenter.start()
            for i in range(args.frames + 5):  # the first 5 of a turn warm up
                before, _ = stats()
                started = time.perf_counter()
                camera.publish(seq=seq, **frame)
                seq += 1
                deadline = started + 5.0
                while stats()[0] == before:
                    if time.perf_counter() > deadline:
                        sys.exit(f"bench_python: the {kind} segmenter published nothing for frame {seq - 1}")
                    time.sleep(0.0001)
                round_trip = (time.perf_counter() - started) * 1000.0
                if i >= 5:
                    results[kind]["function"].append(stats()[1])
                    results[kind]["round_trip"].append(round_trip)
            segmenter.stop()
        print(f"  segmenter round {round_ + 1}/{args.rounds} done", file=sys.stderr)
    return results


def bench_raycasts(domain: int) -> dict[str, list[float]]:
    server_exe = args.build_dir / "server/app/semfuse-server"
    camera_exe = args.build_dir / "client/semfuse-camera"
    dds = ["--domain-id", str(domain), "--dds-profile", str(PROFILE), "--log-level", "warn"]
    with tempfile.TemporaryDirectory() as tmp:
        server = subprocess.Popen([server_exe, *dds, "--legend", "synthetic", "--map", f"{tmp}/bench.vdb",
                                   "--autosave-period", "0"])
        try:
            subprocess.run([camera_exe, *dds, "--source", "synthetic", "--frames", "120", "--rate", "0"], check=True)
            python_client = semfuse.MapClient(domain_id=domain, timeout=10)
            status = python_client.status()
            print(f"  map: {status.frames_integrated} frames, {status.allocated_voxels} voxels", file=sys.stderr)
            cpp_client = _semfuse_bench.CppMapClient(domain)
            poses = [np.vstack([np.array(v).reshape(3, 4), [0, 0, 0, 1]]) for v in VIEWS]
            k = (CAMERA.width, CAMERA.height, CAMERA.fx, CAMERA.fy, CAMERA.cx, CAMERA.cy)
            times: dict[str, list[float]] = {"cpp": [], "python": []}
            for i in range(args.raycasts + 4):  # the first 4 of each warm up
                pose = poses[i % len(poses)]
                cpp_ms = cpp_client.raycast_ms(pose, *k)
                started = time.perf_counter()
                view = python_client.raycast(pose, CAMERA)
                python_ms = (time.perf_counter() - started) * 1000.0
                assert view["labels"].shape == (480, 640)
                if i >= 4:
                    times["cpp"].append(cpp_ms)
                    times["python"].append(python_ms)
            return times
        finally:
            server.terminate()
            server.wait(30)


def median(values: list[float]) -> float:
    return statistics.median(values)


def p90(values: list[float]) -> float:
    return sorted(values)[int(0.9 * (len(values) - 1))]


def main() -> int:
    print(f"bench_python: semfuse {semfuse.__version__}, DDS domain {args.domain_id}, "
          f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores", file=sys.stderr)
    cpu_started = time.process_time()
    segmenters = bench_segmenters(args.domain_id)
    raycasts = bench_raycasts(args.domain_id)
    rows = []
    for function, name in (("constant", "constant labels"), ("near_far", "near/far labels")):
        for key, measure in (("function", "labelling function per frame"),
                             ("round_trip", "frame published to result published")):
            cpp, py = segmenters[("cpp", function)][key], segmenters[("python", function)][key]
            rows.append((f"segmenter, {name}: {measure}, median (p90)", f"{median(cpp):.3f} ({p90(cpp):.3f})",
                         f"{median(py):.3f} ({p90(py):.3f})", f"{median(py) - median(cpp):+.3f} ms",
                         "≤ 2 ms" if key == "function" else "—"))
    cpp, py = raycasts["cpp"], raycasts["python"]
    rows.append(("raycast 640x480, every layer, median (p90)", f"{median(cpp):.1f} ({p90(cpp):.1f})",
                 f"{median(py):.1f} ({p90(py):.1f})", f"{median(py) / median(cpp):.3f}x", "≤ 1.1x"))
    print(f"\n{len(segmenters[KINDS[0]]['function'])} frames per segmenter in {args.rounds} alternating rounds; "
          f"{len(cpp)} raycasts per client, alternating; times in ms\n")
    print("| measure | C++ | Python | Python over C++ | target |\n| --- | --- | --- | --- | --- |")
    for row in rows:
        print("| " + " | ".join(row) + " |")
    print(f"\nthis process's CPU: {time.process_time() - cpu_started:.1f} s; "
          f"load average now {os.getloadavg()[0]:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
