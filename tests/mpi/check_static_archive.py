"""usage: check_static_archive.py ARCHIVE.h5
Checks an archive of a minimisation campaign (QS, RAND, COOL, COMPRESS, COOL_COMPRESS,
SHEARED) with h5py: every replica finished, every row is a minimised state that met the
recorded stopping rule, jammed rows have E/N above the energy floor and a non-negative contact
excess, unjammed rows below it; a phi_J search ends on the jammed side of its bracket; SHEARED's
row stands at the strain its quasistatic shear reached (whole strain steps), the others at 0."""
import sys

import h5py
import numpy as np

with h5py.File(sys.argv[1], "r") as f:
    r, ts = f["replicas"], f["timeseries"]
    model = f.attrs["model"]
    model = model.decode() if isinstance(model, bytes) else str(model)
    phi_j_search = model in ("COMPRESS", "COOL_COMPRESS", "SHEARED")
    assert (r["status"][...] == 2).all(), r["status"][...]
    for k in range(r["status"].shape[0]):
        m = int(r["n_samples"][k])
        assert m >= 1
        e = ts["energy_per_particle"][k, :m]
        jammed = ts["jammed"][k, :m]
        assert set(np.unique(jammed)) <= {0.0, 1.0}, jammed
        if phi_j_search:
            assert m == 1 and jammed[0] == 1.0, (model, jammed)
        floor = r["energy_floor"][k]
        assert (e[jammed == 1] >= floor).all() and (e[jammed == 0] < floor).all()
        fmax = ts["max_force"][k, :m]
        assert np.isfinite(fmax).all()
        excess = ts["excess_contacts"][k, :m][jammed == 1]
        assert (excess >= 0).all(), excess
        z = ts["contact_number_nonrattler"][k, :m]
        n_prime = np.round(r["N"][k] * (1 - ts["rattler_fraction"][k, :m]))  # non-rattlers N'
        iso = 4.0 - 2.0 / n_prime  # Z of 2(N' - 1) + 1 contacts among N' disks
        assert (z[jammed == 1] >= iso[jammed == 1] - 1e-12).all(), (z, iso)  # at least isostatic
        assert np.isnan(z[jammed == 0]).all()
        assert (ts["packing_fraction"][k, :m] > 0).all()
        if phi_j_search:
            strain = ts["strain"][k, 0]
            if model == "SHEARED":
                step = r["strain_step"][k]
                reached = np.ceil(r["strain"][k] / step - 1e-9) * step
                assert abs(strain - reached) <= 1e-12 * reached and strain > 0, (strain, reached)
            else:
                assert strain == 0.0, strain
        # every minimiser iteration costs at least one force evaluation
        its = ts["solver_iterations"][k, :m].sum()
        assert r["force_evaluations"][k] >= its, (r["force_evaluations"][k], its)
print("ok")
