"""CF conventions of the result files, one small run of each analysis.

The CF checker of PyPI (cfchecker) needs the UDUNITS-2 C library and downloads the CF
standard-name table when it runs, neither of which a test run here may rely on, so this is
a hand-written check of the rules the project promises (CF-1.8, section numbers in
brackets): every variable has ``units`` [3.1] (a UDUNITS expression of the units in use)
and ``long_name`` [3.2], strings excepted from ``units``; ``flag_values`` and
``flag_meanings`` come together, one blank-free word per value, of the variable's type
[3.5]; a ``_FillValue`` has the variable's type [2.5.1]; every name in a ``coordinates``
attribute exists [5]; and the file declares ``Conventions = "CF-1.8"`` [2.6.1].
"""

import re

import netCDF4
import numpy as np
import pytest

from sweep import cli

#: Units of the quantities the project stores, as UDUNITS products of powers.
_SYMBOLS = {"1", "m", "s", "kg", "N", "Pa", "rad"}
_TERM = re.compile(r"([A-Za-z]+|1)(-?\d+)?")


def _valid_units(text: str) -> bool:
    terms = text.split()
    return bool(terms) and all((m := _TERM.fullmatch(t)) and m.group(1) in _SYMBOLS for t in terms)


def cf_problems(path) -> list[str]:
    """The CF rules above that the file at ``path`` breaks, one line each."""
    problems = []
    with netCDF4.Dataset(path) as nc:
        if getattr(nc, "Conventions", None) != "CF-1.8":
            problems.append("global Conventions is not CF-1.8")
        for name, var in nc.variables.items():
            attrs = {a: var.getncattr(a) for a in var.ncattrs()}
            is_string = var.dtype is str or np.dtype(var.dtype).kind in "SU"
            if "long_name" not in attrs:
                problems.append(f"{name}: no long_name")
            if not is_string:
                if "units" not in attrs:
                    problems.append(f"{name}: no units")
                elif not _valid_units(str(attrs["units"])):
                    problems.append(f"{name}: units {attrs['units']!r} is not a UDUNITS expression")
            if ("flag_values" in attrs) != ("flag_meanings" in attrs):
                problems.append(f"{name}: flag_values and flag_meanings must come together")
            if "flag_values" in attrs:
                values = np.atleast_1d(attrs["flag_values"])
                words = str(attrs["flag_meanings"]).split(" ")
                if len(words) != values.size or any(not w for w in words):
                    problems.append(f"{name}: {values.size} flag_values for flag_meanings {attrs['flag_meanings']!r}")
                if values.dtype != np.dtype(var.dtype):
                    problems.append(f"{name}: flag_values of type {values.dtype}, variable {var.dtype}")
            if "_FillValue" in attrs and not is_string and np.asarray(attrs["_FillValue"]).dtype != np.dtype(var.dtype):
                problems.append(f"{name}: _FillValue of another type than the variable")
            for other in str(attrs.get("coordinates", "")).split():
                if other not in nc.variables:
                    problems.append(f"{name}: coordinates names {other!r}, which does not exist")
    return problems


JOBS = {
    "static": """[grid]\ndelta = [1.1, 1.5]\ndelta_o = 0.2\n[static]\nprestretch = "analytic"\n"""
              """rho = {start = 0.2, stop = 1.0, num = 5}\n""",
    "linear": """[grid]\ndelta = [1.1, 1.5]\ndelta_o = 0.2\n[linear]\nprestretch = "analytic"\n"""
              """modes = [[1, 0], [1, 1]]\n""",
    "backbone": """[grid]\ndelta = 1.1\ndelta_o = 0.2\n[backbone]\nprestretch = "analytic"\n"""
                """amplitude = {start = 0.001, stop = 0.1, num = 3}\n""",
    "response": """[grid]\ndelta = 1.1\ndelta_o = 0.2\nP0 = 0.01\nc = 2.0\n[response]\nparameter = "Omega"\n"""
                """values = {start = 30.0, stop = 34.0, num = 3}\nprestretch = "analytic"\n""",
    "continuation": """[grid]\ndelta = [1.1, 2.0]\ndelta_o = 0.2\nOmega = [33.5, 47.35]\nc = 0.5\n"""
                    """cases = [{delta = 1.1, Omega = 33.5}]\n[continuation]\nparameter = "P0"\nstart = 0.0\n"""
                    """stop = 4.0\nprestretch = "analytic"\nds_max = 0.3\nmax_points = 200\n"""
                    """fold_curve = {parameter = "c", start = 0.5, stop = 3.0}\n""",
    "basins": """[grid]\ndelta = 1.1\ndelta_o = 0.2\nOmega = 33.5\nP0 = 1.0\nc = 0.05\n[basins]\n"""
              """prestretch = "analytic"\nic_x = {start = -0.3, stop = 0.3, num = 8}\n"""
              """ic_y = {start = -10.0, stop = 10.0, num = 8}\ntiles = 2\n""",
}


@pytest.mark.parametrize("analysis", sorted(JOBS))
def test_every_analysis_writes_cf_conform_results(tmp_path, analysis, capsys):
    job = tmp_path / f"{analysis}.toml"
    job.write_text(f'[job]\nname = "{analysis}"\nanalysis = "{analysis}"\n' + JOBS[analysis])
    assert cli.main(["run", str(job), "-o", str(tmp_path / f"{analysis}.nc"), "--progress", "none"]) == 0, \
        capsys.readouterr().err
    assert cf_problems(tmp_path / f"{analysis}.nc") == []


def test_the_check_finds_what_it_looks_for(tmp_path):
    path = tmp_path / "bad.nc"
    with netCDF4.Dataset(path, "w") as nc:
        nc.createDimension("x", 2)
        v = nc.createVariable("a", "i1", ("x",))
        v.setncatts({"units": "furlongs", "flag_values": np.array([0, 1], np.int32), "flag_meanings": "one"})
        w = nc.createVariable("b", "f8", ("x",))
        w.setncatts({"long_name": "b", "units": "m s-1", "coordinates": "nowhere"})
    found = "\n".join(cf_problems(path))
    for expected in ("Conventions", "a: no long_name", "units 'furlongs'", "2 flag_values", "flag_values of type",
                     "coordinates names 'nowhere'"):
        assert expected in found


def test_a_variable_named_after_one_of_its_dimensions_is_refused():
    # xarray would make it a coordinate without an index, and the files would not combine
    from sweep.analyses.base import Variable

    with pytest.raises(ValueError, match="'state' is named after one of its dimensions"):
        Variable("state", ("point", "state"), (2, 3), "f8", "m", "a state per point")
