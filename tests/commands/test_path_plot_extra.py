"""``symkin path --plot`` without matplotlib: a user error naming the plots extra (README, issue 7 §8)."""
from __future__ import annotations

import sys

from symkin.cli import main
from tests.conftest import EXAMPLES


def test_plot_without_matplotlib_names_the_extra(capsys, tmp_path, monkeypatch):
    for name in [m for m in sys.modules if m == "matplotlib" or m.startswith("matplotlib.")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "matplotlib", None)      # as if it were not installed
    target = tmp_path / "fig.png"
    code = main(["path", str(EXAMPLES / "fourbar_appendix.toml"), "--to", "10", "--steps", "5",
                 "--plot", str(target), "--no-progress"])
    err = capsys.readouterr().err
    assert code == 2
    assert "--plot needs matplotlib" in err and "[plots]" in err and "Traceback" not in err
    assert not target.exists()
