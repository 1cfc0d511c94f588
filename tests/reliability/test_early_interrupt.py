"""A Ctrl-C while the program starts (Python importing symkin) exits 130 with one line (issue 20 §2).

Before, a SIGINT in the first ~0.4 s gave Python's ``KeyboardInterrupt`` traceback from inside
an import.  Each run sends SIGINT at an early moment and asserts exit 130, no traceback.
"""
from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
#: a command that runs for seconds after start-up (the interrupt must land while it starts or works)
ARGS = ["path", "catalogue:fourbar_appendix", "--input", "rotation:crank", "--to", "360", "--steps", "5000",
        "--no-progress"]


def _env():
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    return env


def _default_sigint():
    """In the child: SIGINT at its default, as a terminal gives it.

    A test run started in the background by a non-interactive shell ignores SIGINT, and its
    children would inherit that (Python then keeps ``SIG_IGN`` and no Ctrl-C ever arrives).
    """
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _interrupt(cmd, delay):
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=_env(), cwd=ROOT,
                         preexec_fn=_default_sigint)
    time.sleep(delay)
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=60)
    return p.returncode, err.decode()


@pytest.fixture(scope="module")
def interpreter_start():
    """Seconds this machine takes to start Python and run nothing (best of three): the delays below
    are measured from it, since a SIGINT before symkin's first line runs is Python's to answer."""
    times = []
    for _ in range(3):
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-c", "pass"], env=_env(), cwd=ROOT, check=True)
        times.append(time.perf_counter() - t0)
    return min(times)


@pytest.mark.parametrize("delay", [0.03, 0.06, 0.1, 0.2, 0.35])
def test_python_m_symkin_interrupted_while_starting(delay, interpreter_start):
    code, err = _interrupt([sys.executable, "-m", "symkin", *ARGS], 1.5 * interpreter_start + delay)
    assert code == 130, err
    assert "Traceback" not in err and err.strip().splitlines() == ["symkin: interrupted"]


@pytest.mark.skipif(shutil.which("symkin") is None, reason="the console script is not installed")
@pytest.mark.parametrize("delay", [0.05, 0.15])
def test_console_script_interrupted_while_starting(delay, interpreter_start):
    code, err = _interrupt([shutil.which("symkin"), *ARGS], 1.5 * interpreter_start + delay)
    assert code == 130, err
    assert "Traceback" not in err and err.strip().splitlines() == ["symkin: interrupted"]


def test_library_import_keeps_the_callers_handler():
    code = ("import signal, symkin, symkin.cli; "
            "assert signal.getsignal(signal.SIGINT) is signal.default_int_handler; print('ok')")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=_env(), cwd=ROOT,
                         preexec_fn=_default_sigint)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr
