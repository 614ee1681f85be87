"""`shockfriction impact`: prints the exact states; bad input exits with status 2."""

import pytest

from shockfriction.cli import main


def test_impact_command_prints_exact_states(capsys):
    with pytest.raises(SystemExit) as exc:  # typer's standalone mode exits with status 0
        main(["impact", "Al6061-T6", "Al6061-T6", "--velocity", "250 m/s", "--strength", "epp"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    assert "125.0000 m/s" in out  # symmetric: half the impact velocity
    assert "1.82959 GPa" in out  # rho0 Us up = 2703 (5240 + 1.4 * 125) 125
    assert "HEL" in out and "plastic shock speed" in out


@pytest.mark.parametrize("args", [["--velocity", "250"], ["--velocity", "-3 m/s"],
                                  ["--velocity", "250 m/s", "--strength", "hard"]])
def test_impact_command_refuses_bad_input(args, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["impact", "Al6061-T6", "SS304", *args])
    assert exc.value.code == 2
