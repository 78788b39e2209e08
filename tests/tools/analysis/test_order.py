"""psi6 on configurations of known order, and configuration frames read from a real archive:
their strains, the last one equal to the final configuration, the animation and the report."""
import numpy as np
import pytest
from PIL import Image

from jamsim_analysis import open_archives, order, pictures, report
from jamsim_analysis.archive import FinalConfiguration
from jamsim_analysis.errors import AnalysisError


def triangular_in_sheared_cell(m=13, q=15, a=1.0):
    """A triangular lattice of m x q sites (spacing a) in the square Lees-Edwards cell L = m a:
    q rows spaced L/q (13/15 = 0.8667 against sqrt(3)/2 = 0.8660: 0.08 % strain), row j shifted
    by j a/2, which the cell's images continue when the box strain is -5.5/13 (q a/2 = 7.5 a
    = -5.5 a modulo L)."""
    L = m * a
    gamma = -5.5 / m
    j, i = np.meshgrid(np.arange(q), np.arange(m), indexing="ij")
    lab_x = (i * a + j * a / 2).ravel()
    y = (j * L / q).ravel()
    lab_x = lab_x - L * np.floor((lab_x - gamma * y) / L)  # into the parallelogram
    return lab_x, y, L, gamma


def test_triangular_lattice_is_fully_ordered():
    lab_x, y, L, gamma = triangular_in_sheared_cell()
    psi = order.psi6_per_disk(lab_x, y, L, gamma)
    assert len(psi) == 13 * 15
    # The 0.08 % distortion moves bond angles by < 1e-3 rad: |psi6| within 6e-3 of 1.
    assert abs(psi.mean()) > 0.99
    assert np.abs(psi).min() > 0.99


def test_square_lattice_and_random_disks_are_not():
    rng = np.random.default_rng(3)
    m = 20
    j, i = np.meshgrid(np.arange(m), np.arange(m), indexing="ij")
    # A tiny jitter breaks the square lattice's degenerate (cocircular) Delaunay triangles.
    lab_x = i.ravel() + 1e-3 * rng.standard_normal(m * m)
    y = j.ravel() + 1e-3 * rng.standard_normal(m * m)
    psi = order.psi6_per_disk(np.mod(lab_x, m), np.mod(y, m), float(m), 0.0)
    assert abs(psi.mean()) < 0.5 and np.abs(psi).mean() < 0.6
    n = 400
    x, y = rng.uniform(0, 20, n), rng.uniform(0, 20, n)
    psi = order.psi6_per_disk(x, y, 20.0, 0.0)
    # Random points: the global mean of N unit-bounded terms is ~ N^-1/2 = 0.05.
    assert abs(psi.mean()) < 5 / np.sqrt(n)


def test_psi6_is_invariant_under_the_choice_of_cell_origin():
    lab_x, y, L, gamma = triangular_in_sheared_cell()
    rng = np.random.default_rng(1)
    lab_x = lab_x + 0.05 * rng.standard_normal(len(lab_x))  # a disordered crystal
    a = order.psi6(FinalConfiguration(lab_x - gamma * y, y, np.ones_like(y), L, gamma))
    shift_y = y + 0.37 * L  # the same configuration seen from another origin
    wrapped = shift_y >= L
    y2 = np.where(wrapped, shift_y - L, shift_y)
    x2 = np.where(wrapped, lab_x - gamma * L, lab_x)  # the image below: lab x moves by -gamma L
    b = order.psi6(FinalConfiguration(x2 - gamma * y2, y2, np.ones_like(y), L, gamma))
    assert a == pytest.approx(b, abs=1e-12)


def test_frames_of_an_archive(frames_archive, tmp_path):
    run = open_archives(frames_archive)
    for r in run.done()["replica"]:
        strains, configurations = run.frames(int(r))
        assert len(configurations) == 6
        assert np.allclose(strains, np.arange(6) * 0.1, atol=1e-12)
        final = run.final(int(r))
        assert np.array_equal(configurations[-1].x, final.x) and np.array_equal(configurations[-1].y, final.y)
        assert configurations[-1].box_strain == final.box_strain
        assert not np.array_equal(configurations[0].x, configurations[1].x)
    gif = tmp_path / "frames.gif"
    assert pictures.animate_frames(run, 0, str(gif), max_frames=4) == 4
    with Image.open(gif) as image:
        assert image.n_frames == 4
    series, summary = order.order_by_size_ratio(run)
    assert set(series["replica"]) == {0, 1} and len(series) == 12
    assert list(summary["size_ratio"]) == [1.0] and summary["replicas"].iat[0] == 2
    assert summary["psi6_local"].between(0, 1).all()


def test_report_with_frames(frames_archive, tmp_path):
    out = tmp_path / "report"
    report.build_report([frames_archive], str(out), report.ReportOptions(n_boot=0))
    text = (out / "report.md").read_text()
    assert "Bond-orientational order over strain" in text
    assert (out / "psi6.png").exists() and (out / "frames_size_ratio_1.gif").exists()
    assert "psi6 size ratio 1" in text


def test_no_frames_is_one_clear_error(flow_archive):
    run = open_archives(flow_archive)
    assert not run.has_frames(0)
    with pytest.raises(AnalysisError, match="keeps no configuration frames"):
        run.frames(0)
