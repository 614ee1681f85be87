"""Units at the edge and readable deck errors."""

import pytest

from shockfriction.deck.base import DeckModel, validate
from shockfriction.errors import DeckError
from shockfriction.units import PositiveLength, Pressure, Temperature, UnitError, Velocity, to_si


@pytest.mark.parametrize(
    "text, kind, expected",
    [
        ("250 m/s", "velocity", 250.0),
        ("10 GPa", "pressure", 1e10),
        ("20 um", "length", 20e-6),
        ("1 ns", "time", 1e-9),
        ("26.85 degC", "temperature", 300.0),
        ("1 kbar", "pressure", 1e8),
        ("6.52 1/Mbar", "inverse_pressure", 6.52e-11),
        ("117 W/(m*K)", "conductivity", 117.0),
    ],
)
def test_to_si_converts_to_si(text, kind, expected):
    assert to_si(text, kind) == pytest.approx(expected, rel=1e-12)


def test_wrong_dimension_is_refused_with_the_expectation():
    with pytest.raises(UnitError, match="expected a pressure such as '10 GPa'"):
        to_si("10 m/s", "pressure")


def test_bare_number_is_refused_for_a_dimensional_quantity():
    with pytest.raises(UnitError, match="with its unit"):
        to_si(10.0, "velocity")
    assert to_si(0.3, "dimensionless") == 0.3


class _Section(DeckModel):
    thickness: PositiveLength
    pressure: Pressure


class _Deck(DeckModel):
    velocity: Velocity
    temperature: Temperature
    layer: _Section


def test_valid_deck_is_converted_once_to_si():
    d = validate(_Deck, {"velocity": "200 m/s", "temperature": "300 K",
                         "layer": {"thickness": "20 um", "pressure": "10 GPa"}})
    assert d.layer.thickness == pytest.approx(2e-5)
    assert d.layer.pressure == 1e10


@pytest.mark.parametrize(
    "data, fragments",
    [
        ({"velocity": "200 m/s", "temperature": "300 K", "layer": {"thickness": "20 um", "pressure": "10 m/s"}},
         ["layer.pressure", "'10 m/s'", "pressure such as"]),
        ({"velocity": "200 m/s", "temperature": "300 K", "layer": {"thickness": "-20 um", "pressure": "1 GPa"}},
         ["layer.thickness", "'-20 um'", "greater than 0"]),
        ({"velocity": "200 m/s", "layer": {"thickness": "20 um", "pressure": "1 GPa"}},
         ["temperature is missing"]),
        ({"velocity": "200 m/s", "temperature": "300 K", "colour": "red",
          "layer": {"thickness": "20 um", "pressure": "1 GPa"}},
         ["colour", "no such key"]),
    ],
)
def test_bad_deck_message_names_field_value_and_expectation(data, fragments):
    with pytest.raises(DeckError) as info:
        validate(_Deck, data, "deck.toml")
    msg = str(info.value)
    assert msg.startswith("deck.toml: ")
    for frag in fragments:
        assert frag in msg


def test_cli_deck_error_keeps_bracketed_dimension_text(capsys):
    """pint's '[length]' must survive the rich console (markup escaped)."""
    from shockfriction.cli import main

    with pytest.raises(SystemExit) as info:
        main(["materials", "[nope]"])
    assert info.value.code == 2
    assert "'[nope]'" in capsys.readouterr().err


SUBGRID_DECK = """model = "viscoplastic"
material = "Al7075-T6"
other_material = "Steel4340"
duration = "2 ns"
dt = "1 ns"
[column]
{column}
[friction]
mu0 = 0.05
f = 0.3
[[loading]]
times = ["0 us"]
slip_velocity = ["250 m/s"]
normal_stress = ["5 GPa"]
"""


@pytest.mark.parametrize("column, smallest", [('thickness = "1 nm"\ncells = 200', "5e-12 m"),
                                              ('thickness = "2 um"\ncells = 200\ngrading = 1.2', "5.83e-23 m"),
                                              ('thickness = "2 um"\ncells = 2000\ngrading = 2.0', "of 0 m")])
def test_a_column_finer_than_an_atomic_spacing_is_a_deck_error(column, smallest, tmp_path, capsys):
    """A sub-grid column whose smallest cell is below MIN_CELL = 1e-10 m exits 2 naming thickness, cells, grading
    and the bound.  Before: 5 pm cells ran 41 of 50 steps to the Picard sweep limit (exit 0), 6e-23 m cells stopped
    at the first step (exit 3), and 2^2000 was an internal OverflowError."""
    from shockfriction.cli import main

    deck = tmp_path / "d.toml"
    deck.write_text(SUBGRID_DECK.format(column=column))
    with pytest.raises(SystemExit) as info:
        main(["subgrid", str(deck), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert info.value.code == 2
    assert "column" in err and smallest in err and "expected at least 1e-10 m" in err and "Traceback" not in err


def test_a_slide_line_column_finer_than_an_atomic_spacing_is_a_deck_error(tmp_path, capsys):
    """The same bound on a slide line's sub-grid friction table: the cone shot's column graded 1.5 over its 500 cells
    (a first cell of 9e-94 m) exits 2 naming the friction table."""
    from pathlib import Path

    from shockfriction.cli import main

    cone = (Path(__file__).resolve().parents[1] / "examples" / "cone_in_cylinder.toml").read_text()
    assert cone.count('cells = 500,') == 1
    deck = tmp_path / "cone.toml"
    deck.write_text(cone.replace('cells = 500,', 'cells = 500, grading = 1.5,'))
    with pytest.raises(SystemExit) as info:
        main(["run", str(deck), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert info.value.code == 2
    assert "slide_lines[0].friction" in err and "smallest cell of 9e-94 m: expected at least 1e-10 m" in err
