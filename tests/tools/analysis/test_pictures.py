"""Contact network, forces and rattlers of configurations, against a brute-force search over
explicit Lees-Edwards images and against the observables jamsim recorded for the same states."""
import numpy as np

import jamsim_analysis as ja
from jamsim_analysis import pictures
from jamsim_analysis.archive import FinalConfiguration


def brute_force_contacts(final, alpha):
    """{(i, j): force} over the 9 images (m, n) of j: lab position (x + m L + gamma (y + n L), y + n L)."""
    L, g = final.box_side, final.box_strain
    lab = np.column_stack([final.x + g * final.y, final.y])
    out = {}
    for i in range(len(final.x)):
        for j in range(i + 1, len(final.x)):
            d = 0.5 * (final.diameter[i] + final.diameter[j])
            best = min(np.hypot(*(lab[i] - (lab[j] + [m * L + g * n * L, n * L])))
                       for m in (-1, 0, 1) for n in (-1, 0, 1))
            if best < d:
                out[(i, j)] = (1 / d) * (1 - best / d) ** (alpha - 1)
    return out


def test_network_equals_brute_force_across_sheared_boundaries():
    rng = np.random.default_rng(4)
    for gamma, alpha in ((0.0, 2.0), (0.37, 2.5), (-0.49, 2.0)):
        n, L = 60, 7.0
        final = FinalConfiguration(rng.random(n) * L, rng.random(n) * L, np.where(np.arange(n) % 2, 1.4, 1.0), L, gamma)
        net = pictures.contact_network(final, alpha)
        brute = brute_force_contacts(final, alpha)
        found = {(i, j): f for i, j, f in zip(net.i, net.j, net.force)}
        assert found.keys() == brute.keys()
        assert all(np.isclose(found[k], brute[k], rtol=1e-12) for k in brute)


def test_rattlers_are_removed_repeatedly():
    edges = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3),  # K4: 3 contacts each, kept
             (0, 4), (4, 5),  # 4: two contacts, 5: one
             (0, 6), (6, 7), (7, 8), (6, 8)]  # 6 has 3 until 7 and 8 (2 each) go
    i, j = np.array(edges).T
    net = pictures.ContactNetwork(i, j, *np.ones((4, len(edges))))
    assert np.flatnonzero(pictures.rattlers(9, net)).tolist() == [4, 5, 6, 7, 8]


def test_network_reproduces_recorded_pressure_stress_and_contacts(rand_archive, tmp_path):
    """Jammed RAND states: p and sigma of the network equal the recorded ones to 1e-9
    relative, and the non-rattler contact number and rattler fraction equal the recorded
    ones; a picture is written."""
    run = ja.open_archives(rand_archive)
    states = ja.jamming.static_states(run)
    jammed = states[states["jammed"] == 1]
    assert len(jammed) >= 5
    for _, s in jammed.iterrows():
        final = run.final(int(s["replica"]))
        net = pictures.contact_network(final, 2.0)
        p, sigma = net.stress(final.box_side)
        assert np.isclose(p, s["pressure"], rtol=1e-9)
        assert np.isclose(sigma, run.series(int(s["replica"]), "shear_stress")[0], rtol=1e-9, atol=1e-15)
        ratt = pictures.rattlers(len(final.x), net)
        kept = ~ratt[net.i] & ~ratt[net.j]
        assert np.isclose(2 * kept.sum() / (~ratt).sum(), s["contact_number_nonrattler"])
        assert np.isclose(ratt.mean(), s["rattler_fraction"])
    path = tmp_path / "configuration.png"
    pictures.draw_configuration(run.final(int(jammed["replica"].iloc[0])), str(path))
    assert path.stat().st_size > 10000
