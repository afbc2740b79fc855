"""The distribution: a wheel builds from the checkout and carries what the library reads at run time (the maps, the
named scenarios' world files, the robot's URDF), under a name of its own on PyPI."""
import subprocess
import sys
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DATA = [*(ROOT / "tdp" / "maps").rglob("*"), *(ROOT / "tdp" / "worlds").glob("*"), *(ROOT / "sim" / "assets").glob("*")]


def test_the_wheel_carries_the_maps_worlds_and_assets(tmp_path):
    built = subprocess.run([sys.executable, "-m", "pip", "wheel", str(ROOT), "--no-deps", "-q", "-w", str(tmp_path)],
                           capture_output=True, text=True)
    assert built.returncode == 0, built.stderr[-2000:]
    wheel = zipfile.ZipFile(next(tmp_path.glob("tdp_planner-*.whl")))
    names = set(wheel.namelist())
    wanted = {path.relative_to(ROOT).as_posix() for path in DATA if path.is_file()}
    assert wanted and wanted <= names, sorted(wanted - names)
    metadata = wheel.read(next(n for n in names if n.endswith("/METADATA"))).decode()
    assert "Name: tdp-planner" in metadata and "Requires-Python: <3.14,>=3.10" in metadata
