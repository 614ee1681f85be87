"""``shockfriction analyze``: tables, JSON, the stability figure and bad input (exit 2)."""

import json

import pytest

from shockfriction.cli import main

ARGS = ["analyze", "--pair", "Al5083-H111:AISI321", "--velocity", "250 m/s", "--pressure", "10 GPa",
        "--time", "10 us"]


def run(argv, capsys):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    out = capsys.readouterr()
    return exc.value.code, out.out, out.err


def test_json_output_is_strict_json_with_the_thesis_numbers(capsys):
    code, out, _ = run(ARGS + ["--json"], capsys)
    assert code in (0, None)
    data = json.loads(out)
    al, st = data["materials"]
    assert al["material"] == "Al5083-H111" and st["material"] == "AISI321"
    assert al["numbers"]["N1"] == pytest.approx(6.99e-6, abs=1e-8)
    assert st["scales"]["thickness"] == pytest.approx(3.61e-8, abs=1e-10)
    assert data["pressure"] == pytest.approx(10e9) and data["time"] == pytest.approx(1e-5)
    assert data["units"]["thermal_depth"] == "m"
    assert {t["key"]: t["negligible"] for t in al["terms"]}["shear_inertia"] is True
    assert al["max_stable_strain"] == pytest.approx(1.167, abs=1e-3)


def test_table_output_and_plot(tmp_path, capsys):
    png = tmp_path / "stability.png"
    code, out, _ = run(ARGS + ["--time", "10 ns", "--plot", str(png)], capsys)
    assert code in (0, None)
    for text in ("Dimensionless numbers", "N2", "keep", "drop", "largest stable plastic strain", "AISI321"):
        assert text in out
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10_000


def test_melted_operating_point_gives_null_not_nan(capsys):
    code, out, _ = run(ARGS + ["--temperature", "1300 K", "--json"], capsys)
    assert code in (0, None)
    data = json.loads(out)  # strict JSON: NaN would have been written as NaN and fail here
    assert data["materials"][0]["max_stable_strain"] is None
    code, out, _ = run(ARGS + ["--temperature", "1300 K"], capsys)  # the table: words, not nan
    assert code in (0, None) and "none (melted)" in out and "nan" not in out


@pytest.mark.parametrize("change, message", [
    (["--pair", "Al5083-H111:Unobtainium"], "unknown material 'Unobtainium'"),
    (["--pair", "Al5083-H111"], "expected two library materials"),
    (["--velocity", "250 m"], "expected a velocity"),
    (["--pressure", "10"], "expected a pressure such as"),
    (["--time", "-1 us"], "expected a positive time"),
    (["--time", "10 furlongs"], "--time"),
    (["--threshold", "0"], "--threshold"),
    (["--plot", "figure.pdf"], "ending in .png"),
])
def test_bad_input_exits_2_with_a_clear_message(change, message, capsys):
    code, _, err = run(ARGS + change, capsys)
    assert code == 2
    assert message in " ".join(err.split())
