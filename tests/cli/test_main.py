"""The command line as a whole: help that names every unit and no Python type, commands listed in
the order of a session (run, then data, turbulence, studies, inspection)."""
from .conftest import salkit



def test_help_names_units_and_no_python_types():
    for cmd in ("run", "simulate", "focus", "screen", "export", "convert"):
        out = salkit(cmd, "--help").stdout
        assert "<bool>" not in out and "<list[str]>" not in out and "{" not in out.split("\n")[0], cmd
    focus_help = salkit("focus", "--help").stdout
    for opt in ("--nx PIXELS", "--dx METRES", "--dy METRES"):
        assert opt in focus_help
    assert "salkit " in salkit("--version").stdout


def test_commands_in_order():
    lines = salkit("--help").stdout.splitlines()
    listed = [ln.split()[0] for ln in lines[next(i for i, ln in enumerate(lines) if ln.startswith("Commands")) + 1:]
              if ln.startswith("  ") and ln.split()]
    assert listed == ["run", "simulate", "focus", "export", "convert", "screen", "propagate", "sweep", "info",
                      "verify", "examples"]
