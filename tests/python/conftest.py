"""What the Python package's tests share: the programs CMake built (paths from the environment,
see CMakeLists.txt), a DDS domain of the test process's own on the loopback profile, and a
semfuse-server process per test that needs one."""
from __future__ import annotations

import fcntl
import os
import signal
import subprocess
import time
from pathlib import Path

import numpy as np
import pytest

SOURCE_DIR = Path(os.environ.get("SEMFUSE_SOURCE_DIR", Path(__file__).resolve().parents[2]))
LOOPBACK_PROFILE = SOURCE_DIR / "deploy" / "dds" / "localhost.xml"
# Cyclone reads its configuration when this process joins its first domain: before any semfuse object.
os.environ["CYCLONEDDS_URI"] = f"file://{LOOPBACK_PROFILE}"

import semfuse  # noqa: E402  (after CYCLONEDDS_URI)

_held_domain_locks: list = []


def _reserve_test_domain() -> int:
    """A DDS domain no other semfuse test on this host holds (tests/support/test_domain.hpp):
    an flock on /tmp/semfuse-domains/<id>.lock, kept until this process exits."""
    folder = Path("/tmp/semfuse-domains")
    folder.mkdir(exist_ok=True)
    try:
        folder.chmod(0o1777)  # several users on one host share it; best effort
    except OSError:
        pass
    start = os.getpid() % 230
    for k in range(230):
        domain = 1 + (start + k) % 230
        handle = open(folder / f"{domain}.lock", "a")  # noqa: SIM115 (held for the process's life)
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            handle.close()
            continue
        _held_domain_locks.append(handle)
        return domain
    raise RuntimeError(f"no free DDS test domain under {folder}")


# A domain per test process: tests run in parallel.
DOMAIN = _reserve_test_domain()


def reserve_another_domain() -> int:
    """One more domain held by this process: for a test that needs a domain no server is on."""
    return _reserve_test_domain()


def program(variable: str) -> str:
    path = os.environ.get(variable)
    if not path or not Path(path).is_file():
        pytest.fail(f"{variable} does not name a built program (run the tests through ctest)")
    return path


class Process:
    """A child process whose output goes to a log file; stopped with SIGTERM (then SIGKILL)."""

    def __init__(self, argv: list[str], log: Path) -> None:
        self.argv = argv
        self.log = log
        self._log_file = open(log, "wb")
        self.popen = subprocess.Popen(argv, stdout=self._log_file, stderr=subprocess.STDOUT)

    def wait(self, timeout: float) -> int:
        try:
            return self.popen.wait(timeout)
        finally:
            self._log_file.flush()

    def stop(self, timeout: float = 20.0) -> int:
        if self.popen.poll() is None:
            self.popen.send_signal(signal.SIGTERM)
            try:
                self.popen.wait(timeout)
            except subprocess.TimeoutExpired:
                self.popen.kill()
                self.popen.wait()
        self._log_file.close()
        return self.popen.returncode

    def output(self) -> str:
        self._log_file.flush()
        return self.log.read_text(errors="replace")


class Server(Process):
    """semfuse-server on the test's domain and the loopback profile, ready once its status is seen."""

    def __init__(self, tmp: Path, *args: str, name: str = "server") -> None:
        argv = [program("SEMFUSE_SERVER_EXE"), "--domain-id", str(DOMAIN), "--dds-profile", str(LOOPBACK_PROFILE),
                "--log-level", "warn", "--map", str(tmp / f"{name}.vdb"), *args]
        super().__init__(argv, tmp / f"{name}.log")
        self.client = semfuse.MapClient(domain_id=DOMAIN, timeout=10.0)
        deadline = time.monotonic() + 30
        while True:
            status = self.client.latest_status()
            if status is not None and status.uptime_s >= 0 and self._serves():
                break
            if self.popen.poll() is not None or time.monotonic() > deadline:
                pytest.fail(f"semfuse-server did not come up:\n{self.output()}")
            time.sleep(0.05)

    def _serves(self) -> bool:
        try:
            self.client.status(timeout=2.0)
            return True
        except semfuse.CallTimeout:
            return False

    def wait_until(self, done, timeout: float = 20.0) -> semfuse.ServerStatus:
        """The server's status once `done(status)` holds; fails the test at the timeout."""
        deadline = time.monotonic() + timeout
        while True:
            status = self.client.status()
            if done(status):
                return status
            if time.monotonic() > deadline:
                pytest.fail(f"server status never satisfied the condition: {status!r}\n{self.output()}")
            time.sleep(0.1)


# The scene the tests publish: a wall 2 m in front of a camera that slides along x. Pixels left of
# the world's x = 0 show a table, right of it a box (labels of the synthetic legend).
CAMERA = semfuse.Intrinsics(640, 480, 525.0, 525.0, 319.5, 239.5)
WALL_Z = 2.0
VOXEL = 0.01  # the server's default
TABLE, BOX = 4, 6


def wall_pose(seq: int) -> np.ndarray:
    pose = np.eye(4)
    pose[0, 3] = 0.02 * (seq % 10) - 0.1
    return pose


def wall_frame(seq: int) -> dict:
    """Depth, colour and pose of frame `seq` of the wall scene, as CameraPublisher.publish takes them."""
    depth = np.full((CAMERA.height, CAMERA.width), WALL_Z, np.float32)
    color = np.zeros((CAMERA.height, CAMERA.width, 3), np.uint8)
    color[..., 0] = 200
    color[..., 1] = np.arange(CAMERA.width, dtype=np.uint32)[None, :] % 256
    color[..., 2] = seq % 256
    return {"depth": depth, "color": color, "pose": wall_pose(seq), "intrinsics": CAMERA}


def wall_labels(frame: semfuse.Frame) -> np.ndarray:
    """TABLE where the pixel's ray meets the wall left of x = 0, BOX right of it."""
    u = np.arange(frame.intrinsics.width, dtype=np.float64)
    x_world = (u - frame.intrinsics.cx) / frame.intrinsics.fx * frame.depth[0, :] + frame.pose[0, 3]
    row = np.where(x_world < 0.0, TABLE, BOX).astype(np.uint16)
    return np.repeat(row[None, :], frame.intrinsics.height, axis=0)


def build_wall(server: Server, frames: range, camera_id: str = "wall", segment=wall_labels) -> None:
    """Publishes `frames` of the wall with a segmenter (`segment`) labeling them, each after the last was fused."""
    camera = semfuse.CameraPublisher(camera_id, color_encoding="raw", domain_id=DOMAIN)
    assert camera.wait_for_server(10)
    with semfuse.Segmenter(segment, segmenter_id="wall-labels", domain_id=DOMAIN) as segmenter:
        wait_for(lambda: camera.matched_readers == 2, what="the server and the segmenter")
        for seq in frames:
            done = server.client.status().segmentations_integrated
            camera.publish(seq=seq, **wall_frame(seq))
            wait_for(lambda: server.client.status().segmentations_integrated > done, what=f"frame {seq}'s labels")
        assert segmenter.stats().failed == 0


def wait_for(condition, timeout: float = 10.0, what: str = "condition") -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            pytest.fail(f"timed out waiting for {what}")
        time.sleep(0.01)


@pytest.fixture
def domain() -> int:
    return DOMAIN


@pytest.fixture
def server(tmp_path: Path):
    """A semfuse-server with the synthetic legend and the defaults (1 cm voxels, bayes label rule),
    except that it integrates every frame in order: under load the default integrates a camera's
    newest posed frame and skips the rest, and the tests count what was integrated."""
    s = Server(tmp_path, "--legend", "synthetic", "--autosave-period", "0", "--max-queue-wait", "0")
    yield s
    assert s.stop() == 0, s.output()
