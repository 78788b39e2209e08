"""Fixtures of the jamsim_analysis tests (the package is found through pytest.ini's
pythonpath, tools/ of this checkout): the jamsim executable
(environment variable JAMSIM, as CTest passes it; else build/release/jamsim) and small real
archives made by it from tests/data/campaigns."""
import os
import shutil
import subprocess

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
CAMPAIGNS = os.path.join(ROOT, "tests", "data", "campaigns")


@pytest.fixture(scope="session")
def jamsim():
    path = os.path.abspath(os.environ.get("JAMSIM", os.path.join(ROOT, "build", "release", "jamsim")))
    assert os.access(path, os.X_OK), f"no jamsim executable at {path} (set JAMSIM)"
    return path


def run_campaign(jamsim, workdir, name):
    """Run tests/data/campaigns/<name>.toml on 1 rank in workdir; the archive's path."""
    os.makedirs(workdir, exist_ok=True)
    spec = os.path.join(CAMPAIGNS, f"{name}.toml")
    out = subprocess.run([jamsim, "run", spec], cwd=workdir, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    output = [line.split("=", 1)[1].strip().strip('"') for line in open(spec) if line.startswith("output")][0]
    return os.path.join(workdir, output)


@pytest.fixture(scope="session")
def flow_archive(jamsim, tmp_path_factory):
    return run_campaign(jamsim, str(tmp_path_factory.mktemp("flow")), "analysis_flow")


@pytest.fixture(scope="session")
def rand_archive(jamsim, tmp_path_factory):
    return run_campaign(jamsim, str(tmp_path_factory.mktemp("rand")), "analysis_rand")


@pytest.fixture(scope="session")
def small_archive(jamsim, tmp_path_factory):
    return run_campaign(jamsim, str(tmp_path_factory.mktemp("small")), "small")


@pytest.fixture
def copy_of(tmp_path):
    def copy(path, name):
        target = tmp_path / name
        shutil.copy(path, target)
        return str(target)
    return copy


@pytest.fixture(scope="session")
def frames_archive(jamsim, tmp_path_factory):
    return run_campaign(jamsim, str(tmp_path_factory.mktemp("frames")), "analysis_frames")
