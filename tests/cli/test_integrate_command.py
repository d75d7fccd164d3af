"""``blockmesh integrate`` through the command line's main()."""

from __future__ import annotations

import json

import pytest
from helpers import run_cli

_KEYS = {
    "value",
    "error_estimate",
    "converged",
    "level",
    "order",
    "rule",
    "cells",
    "points",
    "exact",
    "exact_error",
    "message",
}


def test_cli_json(capsys):
    code, out, _ = run_cli(
        capsys,
        "integrate",
        "usp",
        "--function",
        "(0.2*x+0.3*y)^19",
        "--level",
        "1",
        "--order",
        "10",
        "--exact",
        "--json",
    )
    payload = json.loads(out)
    assert code == 0
    assert set(payload) == _KEYS
    assert payload["exact"] == "5832661838294956841/8400000000000000000"
    assert payload["cells"] == 6 and payload["rule"] == "paper" and payload["converged"]
    assert payload["points"] in (6 * 550, 6 * 550 + 6 * 660)  # + the check one order higher
    assert abs(payload["value"] - 0.6943645045589234) < 1e-15
    assert payload["exact_error"] < 1e-15 and payload["error_estimate"] < 1e-6


def test_json_keys_are_always_there(capsys):
    code, out, _ = run_cli(capsys, "integrate", "sp", "-f", "x*y", "--json")
    payload = json.loads(out)
    assert code == 0 and set(payload) == _KEYS
    assert payload["exact"] is None and payload["exact_error"] is None
    assert payload["error_estimate"] >= 0


def test_cli_tolerance_and_text(capsys):
    code, out, _ = run_cli(
        capsys, "integrate", "sp", "-f", "cos(30*(x + y))", "--tol", "1e-11", "--json"
    )
    payload = json.loads(out)
    assert code == 0 and payload["converged"] and payload["error_estimate"] <= 1e-11
    assert set(payload) == _KEYS
    assert abs(payload["value"] + 0.007436177299024373) <= 1e-11
    code, out, _ = run_cli(
        capsys, "integrate", "--polygon", "0,0 2,0 3,1 1,3 0,2", "-f", "x*y", "--exact"
    )
    assert code == 0 and "exact" in out and "value" in out and "error estimate" in out
    code, out, err = run_cli(
        capsys,
        "integrate",
        "usp",
        "-f",
        "sqrt((x-0.5)^2+(y-0.5)^2)",
        "--tol",
        "1e-15",
        "--max-level",
        "1",
    )
    assert code == 1 and "not reached" in err


def test_a_singular_integrand_warns_and_shows_the_estimate(capsys):
    code, out, err = run_cli(capsys, "integrate", "sp", "-f", "1/(x-0.3)")
    assert code == 0
    estimate = float(out.split("error estimate")[1].split()[0])
    assert estimate > 1
    assert "warning: the integral is not resolved" in err and "--level" in err


def test_overflow_and_huge_requests_are_errors_not_numbers(capsys):
    """`-f 1e308*y` printed inf with exit 0, and --exact/--json crashed (issue 14)."""
    strip = ("--polygon", "0,0 10,0 10,1 0,1")
    for extra in ((), ("--json",), ("--exact", "--json"), ("--exact",)):
        code, out, err = run_cli(capsys, "integrate", *strip, "-f", "1e308*y", *extra)
        assert code == 2 and "the integral overflows" in err and "Traceback" not in err
        assert "inf" not in out
    code, _, err = run_cli(capsys, "integrate", "sp", "-f", "x", "--order", "999", "--level", "5")
    assert code == 2 and "38,841,120,000 evaluations" in err and "(--max-points)" in err
    code, _, _ = run_cli(capsys, "integrate", "sp", "-f", "x", "--max-points", "100")
    assert code == 2


def test_a_finite_integral_of_huge_values_is_judged_without_overflow(capsys):
    """`-f 1e308*y` over sp: the integral (-6.7e307) is finite, but sum |integral| is not; the
    tolerance was inf, so the result always "converged", and numpy's overflow warning leaked."""
    code, out, err = run_cli(capsys, "integrate", "sp", "-f", "1e308*y", "--json")
    result = json.loads(out)
    assert code == 0 and "overflow" not in err and "Traceback" not in err
    assert result["value"] == pytest.approx(-(1e308 / 3) * 2, rel=1e-12)
    assert 0 < result["error_estimate"] < 1e-12 * abs(result["value"]) and result["converged"]


def test_expression_errors_point_at_the_place(capsys):
    code, _, err = run_cli(capsys, "integrate", "sp", "-f", "x + os")
    assert code == 2 and "unknown name 'os'" in err
    code, _, err = run_cli(capsys, "integrate", "sp", "-f", "sin(x)", "--exact")
    assert code == 2 and "not a polynomial" in err
    code, _, err = run_cli(capsys, "integrate", "sp", "-f", "x+")
    lines = err.splitlines()
    assert code == 2 and lines[0].endswith("at column 3")
    assert lines[2].index("^") == lines[1].index("x+") + 2  # after the '+', not under the x
    code, _, err = run_cli(capsys, "integrate", "sp", "-f", "pi/(1e-400 + 0*y)", "--exact")
    assert code == 2 and "too small for a float64" in err


def test_a_mesh_file_is_integrated_over_at_its_own_level(tmp_path, capsys):
    """A refined mesh is a valid thing to integrate over (issue 11): .npz read back, level 2."""
    import blockmesh

    path = tmp_path / "l.npz"
    blockmesh.write(blockmesh.load_domain("l-shape").mesh(2), path)
    code, out, _ = run_cli(capsys, "integrate", str(path), "-f", "x*y", "--exact", "--json")
    payload = json.loads(out)
    assert code == 0 and payload["level"] == 2 and payload["cells"] == 24 * 36
    _, reference, _ = run_cli(capsys, "integrate", "l-shape", "-f", "x*y", "--json")
    assert payload["value"] == json.loads(reference)["value"]
    assert payload["exact_error"] < 1e-14
    code, out, _ = run_cli(capsys, "integrate", str(path), "-f", "x*y", "--level", "1", "--json")
    assert code == 0 and json.loads(out)["cells"] == 24 * 216  # one level added, as mesh counts
    assert json.loads(out)["level"] == 3


def test_a_locally_refined_mesh_file_takes_no_more_levels(tmp_path, capsys):
    import blockmesh

    domain = blockmesh.load_domain("l-shape")
    path = tmp_path / "local.npz"
    blockmesh.write(blockmesh.refine(domain.mesh(1), cells=[0, 1]), path)
    code, out, _ = run_cli(capsys, "integrate", str(path), "-f", "1", "--json")
    assert code == 0 and json.loads(out)["value"] == 3.0
    code, _, err = run_cli(capsys, "integrate", str(path), "-f", "1", "--level", "1")
    assert code == 2 and "--level" in err and "polygon" in err
