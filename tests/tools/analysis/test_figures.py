"""The report's figures show what they claim: g_y(x) with every curve, one panel per (model,
N, phi) and no colour twice in a panel; pressure distributions without a legend over the data
(a colour bar for phi); legends beside the axes; collapse titles with the fitted values, their
errors and chi2/dof, a rejected fit marked; the configuration picture titled with the
accumulated strain (not the wrapped Lees-Edwards offset) and a legend of its marks."""
import os

import matplotlib
import numpy as np
import pandas as pd

import jamsim_analysis as ja
from jamsim_analysis import figures, pictures
from jamsim_analysis.archive import FinalConfiguration
from synthetic import flow_replicas
from test_report import REPORT, call

PHIS = (0.80, 0.82, 0.84, 0.86)
RATES = (1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5)


def synthetic_curves():
    x = np.linspace(0.5, 20, 40)
    curves, minima = {}, []
    for phi in PHIS:
        for rate in RATES:
            xm = 2 + 3 * (rate / 1e-2) ** -0.2 * (1 + phi - 0.8)
            g = -np.sin(np.pi * x / (2 * xm)) * np.exp(-x / 10)
            curves[("RD0", 1024, phi, rate)] = (x, g, np.full(len(x), 0.01))
            minima.append(dict(model="RD0", N=1024, phi=phi, rate=rate, x_min=xm, x_min_error=0.1, seeds=2))
    return curves, pd.DataFrame(minima)


def curve_lines(ax):
    return [line for line in ax.get_lines() if line.get_label().startswith("rate ")]


def test_correlation_figure_draws_every_curve(tmp_path):
    curves, minima = synthetic_curves()
    fig = figures.correlation_figure(curves, minima, str(tmp_path / "c.png"))
    panels = [ax for ax in fig.axes if ax.get_visible() and ax.get_title().startswith("RD0, N = 1024, phi = ")]
    assert len(panels) == len(PHIS)
    drawn = 0
    for ax, phi in zip(panels, PHIS):
        assert ax.get_title().endswith(f"phi = {phi:g}")
        lines = curve_lines(ax)
        assert sorted(float(line.get_label()[5:]) for line in lines) == sorted(RATES)
        colours = {matplotlib.colors.to_hex(line.get_color()) for line in lines}
        assert len(colours) == len(lines)  # no colour twice in a panel
        # each line is the curve of its rate
        for line in lines:
            x, g, _ = curves[("RD0", 1024, phi, float(line.get_label()[5:]))]
            assert np.array_equal(line.get_ydata(), g)
        drawn += len(lines)
    assert drawn == len(curves) == 28
    growth = [ax for ax in fig.axes if ax.get_title().startswith("$x_{min}$")][0]
    assert len([c for c in growth.containers]) == len(PHIS)
    assert os.path.getsize(tmp_path / "c.png") > 20000


def legend_outside(fig, ax):
    fig.canvas.draw()
    legend = ax.get_legend()
    return legend is None or legend.get_window_extent().x0 >= ax.get_window_extent().x1


def test_pressure_distribution_has_no_legend_over_the_data(tmp_path):
    rng = np.random.default_rng(1)
    rows = [dict(model=m, N=n, phi=phi, jammed=1, pressure=rng.lognormal(np.log(phi - 0.83), 0.3))
            for m in ("RAND", "COOL") for n in (16, 32, 64) for phi in np.round(np.linspace(0.84, 0.9, 7), 3)
            for _ in range(12)]
    rows += [dict(model="RAND", N=16, phi=0.80, jammed=0, pressure=0.0)] * 5
    states = pd.DataFrame(rows)
    fig = figures.pressure_distribution_figure(states, str(tmp_path / "p.png"))
    panels = [ax for ax in fig.axes if ax.get_title().startswith(("RAND", "COOL"))]
    assert len(panels) == 6
    for ax in panels:
        assert ax.get_legend() is None
        assert len(ax.get_lines()) == 7  # one step histogram per phi
    assert any(ax.get_ylabel() == r"$\phi$" for ax in fig.axes)  # the colour bar
    # the generic histogram keeps its legend (30+ entries) beside the axes
    samples = {f"phi {k}": rng.normal(size=40) for k in range(34)}
    fig = figures.histogram_figure(samples, "x", str(tmp_path / "h.png"))
    assert legend_outside(fig, fig.axes[0])


def test_collapse_title_has_values_errors_and_chi2(tmp_path):
    pts = ja.collapse_points(ja.group_averages(flow_replicas(np.random.default_rng(3)), ["pressure"]), "pressure")
    fit = ja.fit_collapse(pts, degree=2)
    fig = figures.collapse_figure(fit, str(tmp_path / "a.png"), label="RD0 pressure, window chosen from the data")
    title = fig.axes[0].get_title()
    assert "window chosen from the data" in title and "REJECTED" not in title
    for name in ("phi_J", "q", "znu"):
        value, error = fit.values[name], fit.errors[name]
        assert figures.value_with_error(value, error) in title
    assert f"/dof = {fit.chi2_per_dof:.2f} ({fit.dof} dof" in title
    pts["error"] *= 0.1
    bad = ja.fit_collapse(pts, degree=2)
    fig = figures.collapse_figure(bad, str(tmp_path / "b.png"), label="every point", failed=True)
    assert fig.axes[0].get_title().startswith("FIT REJECTED") and fig.axes[0].title.get_color() == "tab:red"


def test_value_with_error_keeps_two_digits_of_the_error():
    rng = np.random.default_rng(5)
    for _ in range(200):
        value, error = rng.normal() * 10.0 ** rng.integers(-8, 8), 10.0 ** rng.uniform(-9, 7)
        text = figures.value_with_error(value, error)
        if text.startswith("("):
            mantissa, exponent = text[1:].split(")e")
            v, e = (float(t) * 10.0 ** int(exponent) for t in mantissa.split(" \u00b1 "))
        else:
            v, e = (float(t) for t in text.split(" \u00b1 "))
        # both rounded at the error's second significant digit: at most half of its unit
        assert abs(e - error) <= 0.051 * error and abs(v - value) <= 0.051 * error


def test_picture_title_has_the_accumulated_strain_and_a_legend(tmp_path):
    rng = np.random.default_rng(2)
    n, L = 40, 6.0
    final = FinalConfiguration(rng.random(n) * L, rng.random(n) * L, np.where(np.arange(n) % 2, 1.4, 1.0), L, 0.0)
    pictures.draw_configuration(final, str(tmp_path / "c.png"), strain=2.0)
    assert os.path.getsize(tmp_path / "c.png") > 10000
    title, texts = _picture_texts(final, tmp_path, 2.0)
    assert "strain 2, Lees-Edwards offset +0.000" in title
    assert any(t.startswith("small disk (d = 1)") for t in texts)
    assert any(t.startswith("large disk (d = 1.4)") for t in texts)
    assert any(t.startswith("rattler") for t in texts) and any(t.startswith("contact force") for t in texts)
    title, _ = _picture_texts(final, tmp_path, None)
    assert "strain" not in title.replace("Lees-Edwards offset", "")


def _picture_texts(final, tmp_path, strain):
    """Title and legend texts of draw_configuration's figure (captured before it closes)."""
    captured = {}
    original = pictures.plt.close

    def keep(fig):
        ax = fig.axes[0]
        captured["title"] = ax.get_title()
        captured["texts"] = [t.get_text() for t in ax.get_legend().get_texts()]
        original(fig)

    pictures.plt.close = keep
    try:
        pictures.draw_configuration(final, str(tmp_path / "d.png"), strain=strain)
    finally:
        pictures.plt.close = original
    return captured["title"], captured["texts"]


def test_final_strain_of_real_archives(flow_archive, frames_archive):
    """The accumulated strain of a final configuration is the run's strain on its last whole
    step: congruent to the box offset modulo 1 and within a step of the `strain` parameter."""
    for path in (flow_archive, frames_archive):
        run = ja.open_archives(path)
        for _, rep in run.done().iterrows():
            r = int(rep["replica"])
            strain, box = run.final_strain(r), run.final(r).box_strain
            assert abs(strain - rep["strain"]) <= rep["rate"] * rep["dt"] + 1e-12
            assert abs((strain - box + 0.5) % 1 - 0.5) < 1e-9


def test_report_figures_of_a_flow_campaign(flow_archive, tmp_path):
    """correlation.png has every (phi, rate) curve (its data in correlation.tsv), and the
    configuration picture's caption names the accumulated strain."""
    out = call(REPORT, flow_archive, tmp_path, "--bootstrap", "0")
    assert out.returncode == 0, out.stderr
    curves = pd.read_csv(tmp_path / "correlation.tsv", sep="\t")
    run = ja.open_archives(flow_archive)
    expected = run.done()[["phi", "rate"]].drop_duplicates()
    assert len(curves[["phi", "rate"]].drop_duplicates()) == len(expected) == 12
    md = open(tmp_path / "report.md").read()
    assert "(12 curves, in correlation.tsv" in md
    assert "strain 1, Lees-Edwards offset" in md or "strain 1.000" in md
