"""cmake --install puts the package where the system's Python finds it: the install folder under
/usr/local (and /usr) is on the interpreter's path, and the installed package imports and works
without the build tree."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

BINARY_DIR = Path(os.environ.get("SEMFUSE_BINARY_DIR", ""))


def cache_value(name: str) -> str:
    for line in (BINARY_DIR / "CMakeCache.txt").read_text().splitlines():
        if line.startswith(f"{name}:"):
            return line.split("=", 1)[1]
    raise AssertionError(f"{name} is not in {BINARY_DIR / 'CMakeCache.txt'}")


def test_the_install_folder_is_on_the_system_pythons_path() -> None:
    folder = cache_value("SEMFUSE_PYTHON_INSTALL_DIR")
    python = cache_value("Python3_EXECUTABLE")
    path = subprocess.run([python, "-c", "import sys; print('\\n'.join(sys.path))"], capture_output=True, text=True,
                          env={"PATH": os.environ["PATH"]}, check=True).stdout.split()
    assert f"/usr/local/{folder}" in path, path
    if python.startswith("/usr/bin/"):
        assert f"/usr/{folder}" in path, path


def test_the_installed_package_imports_and_works(tmp_path: Path) -> None:
    prefix = tmp_path / "prefix"
    subprocess.run(["cmake", "--install", str(BINARY_DIR), "--component", "python", "--prefix", str(prefix)],
                   check=True, capture_output=True)
    package = prefix / cache_value("SEMFUSE_PYTHON_INSTALL_DIR") / "semfuse"
    installed = sorted(p.name for p in package.iterdir())
    native = [n for n in installed if n.startswith("_semfuse.") and n.endswith(".so")]
    assert len(native) == 1, installed
    assert installed == sorted(["__init__.py", "_errors.py", "_semfuse.pyi", "py.typed", *native])
    script = ("import semfuse, numpy as np\n"
              "print(semfuse.__file__)\n"
              "client = semfuse.MapClient(domain_id=231, timeout=0.2)\n"
              "try:\n"
              "    client.raycast(np.eye(4), semfuse.Intrinsics(64, 48, 50, 50, 31.5, 23.5))\n"
              "except TimeoutError as e:\n"
              "    print('timeout', e.reason)\n")
    env = {"PATH": os.environ["PATH"], "PYTHONPATH": str(package.parent),
           "CYCLONEDDS_URI": os.environ.get("CYCLONEDDS_URI", "")}
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env, cwd=tmp_path,
                          timeout=60)
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == [str(package / "__init__.py"), "timeout unavailable"]
