import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]

# lavapipe, the CPU Vulkan driver, unless the caller chose a device.
os.environ.setdefault("VK_DRIVER_FILES", "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json")
os.environ.setdefault("WGPU_BACKEND", "vulkan")
os.environ.setdefault("XDG_RUNTIME_DIR", "/tmp")


@pytest.fixture(scope="session")
def tress_bin():
    """The `tress` command of this checkout (TRESS_BIN, else target/debug/tress, built if absent)."""
    path = pathlib.Path(os.environ.get("TRESS_BIN", ROOT / "target" / "debug" / "tress"))
    if not path.exists():
        subprocess.run(["cargo", "build", "-p", "tress-cli"], cwd=ROOT, check=True)
    return path


@pytest.fixture(scope="session")
def renderer():
    import tress

    return tress.Renderer()
