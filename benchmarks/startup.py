"""Start-up and the whole process: ``import mbsym`` and ``mbsym simulate <paper45>`` as a user waits for them.

Measured in fresh processes, interleaved round by round (the machine is shared: the order of the
commands rotates and the minimum over ``--rounds`` rounds is the figure, the median is shown too):

- the baselines ``python -c pass`` (the interpreter) and ``python -c "import casadi, numpy"``;
- ``python -c "import mbsym"`` of this tree, and of a ``--before`` revision (``git archive`` into a
  temporary directory, put first on ``PYTHONPATH``; the repository is only read);
- the whole ``mbsym simulate paper45_fa_ss_gen.fst --stats`` process with the defaults, with a warm
  compile cache (one run beforehand, background compilations waited for), and the same command of the
  ``--before`` revision (its default: cvodes at rtol 1e-8 in CasADi's virtual machine); the ``--stats``
  figures of the last run are reported with it. OpenFAST v5 (ElastoDyn only) runs this deck in 2.21 s
  on this machine kind (issue 4, quoted).

Processes run with Python's bytecode cache (as an installed package: ``pip`` compiles it), each command
once before timing. Also the heavy modules each ``import`` loads (scipy, python-control, matplotlib), as a check of the lazy
imports. Writes the ``startup`` section of benchmarks/README.md.

Run: ``python benchmarks/startup.py [--rounds 7] [--before 7aa058a] [--no-write]``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _report import write_section

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
DECK = ROOT.parent / "shared" / "openfast" / "cases" / "paper45_fa_ss_gen" / "paper45_fa_ss_gen.fst"
OPENFAST_S = 2.21
HEAVY = ("scipy", "control", "matplotlib", "importlib.metadata")


def timed(cmd: list[str], env: dict) -> tuple[float, str]:
    t0 = time.perf_counter()
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
    return time.perf_counter() - t0, out.stdout


def env_for(tree: Path | None) -> dict:
    """Environment of the measured processes: bytecode written and used, as in an installed package (pip
    compiles it at install time; ``PYTHONDONTWRITEBYTECODE`` of a development shell would make every
    process compile mbsym from source), and ``tree`` first on the path."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    if tree is not None:
        env["PYTHONPATH"] = str(tree) + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    return env


def export_revision(rev: str, into: Path) -> Path:
    """The tree of ``rev`` (read from the repository with git archive), ready to import."""
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", rev], capture_output=True, check=True).stdout
    subprocess.run(["tar", "-x", "-C", str(into)], input=archive, check=True)
    return into


def heavy_modules(env: dict, code: str) -> list[str]:
    probe = f"import sys; {code}; print(','.join(m for m in {HEAVY!r} if m in sys.modules))"
    return [m for m in subprocess.run([sys.executable, "-c", probe], env=env, capture_output=True, text=True,
                                      check=True).stdout.strip().split(",") if m]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--before", default="7aa058a", help="revision to compare with (default: the base commit)")
    parser.add_argument("--no-write", action="store_true")
    args = parser.parse_args()
    py = sys.executable
    with tempfile.TemporaryDirectory() as tmp:
        before = export_revision(args.before, Path(tmp)) if args.before else None
        after_env, before_env = env_for(ROOT), env_for(before)
        check = subprocess.run([py, "-c", "import mbsym; print(mbsym.__file__)"], env=before_env, capture_output=True,
                               text=True, check=True).stdout.strip() if before else ""
        assert not before or check.startswith(str(before)), check
        cli = [py, "-m", "mbsym", "simulate", str(DECK), "--stats"]
        commands = {
            "python -c pass": ([py, "-c", "pass"], after_env),
            "import casadi, numpy (baseline)": ([py, "-c", "import casadi, numpy"], after_env),
            "import mbsym": ([py, "-c", "import mbsym"], after_env),
        }
        if before:
            commands[f"import mbsym ({args.before})"] = ([py, "-c", "import mbsym"], before_env)
        if DECK.exists():
            timed(cli, after_env)                                  # warm the compile cache ...
            timed(cli, after_env)                                  # ... (background compilations end with it)
            commands["mbsym simulate paper45 --stats"] = (cli, after_env)
            if before:
                commands[f"mbsym simulate paper45 --stats ({args.before})"] = (cli, before_env)
        for cmd, env in commands.values():                         # bytecode written once, like an install
            timed(cmd, env)
        walls: dict[str, list[float]] = {k: [] for k in commands}
        last: dict[str, str] = {}
        names = list(commands)
        for r in range(args.rounds):
            for k in names[r % len(names):] + names[: r % len(names)]:
                w, out = timed(*commands[k])
                walls[k].append(w)
                last[k] = out
            print(f"round {r + 1}: " + ", ".join(f"{k} {1e3 * walls[k][-1]:.0f} ms" for k in names), flush=True)
        heavy = {"import mbsym": heavy_modules(after_env, "import mbsym")}
        if before:
            heavy[f"import mbsym ({args.before})"] = heavy_modules(before_env, "import mbsym")
    base = min(walls["import casadi, numpy (baseline)"])
    rows = ["| process | min [ms] | median [ms] | minus `import casadi, numpy` [ms] | heavy modules loaded |",
            "|---|---:|---:|---:|---|"]
    for k in names:
        lo, med = 1e3 * min(walls[k]), 1e3 * statistics.median(walls[k])
        extra = "—" if k in ("python -c pass",) or k.startswith("import casadi") else f"{lo - 1e3 * base:+.0f}"
        mods = ", ".join(heavy.get(k, [])) or ("none" if k in heavy else "")
        rows.append(f"| {k} | {lo:.0f} | {med:.0f} | {extra} | {mods} |")
    notes = []
    for k in names:
        if k.startswith("mbsym simulate") and last.get(k):
            s = json.loads(last[k].strip().splitlines()[-1])
            notes.append(f"{k}: method {s.get('method')}" + (f" (compiled: {s.get('compiled')})")
                         + f", {s.get('steps')} steps, integration {1e3 * s['integration_wall_s']:.1f} ms, preparation "
                         f"{1e3 * s['prepare_wall_s']:.0f} ms, outputs {1e3 * s.get('outputs_wall_s', float('nan')):.0f} ms"
                         + (f", error estimate {s['error_estimate']:.1e}" if s.get("error_estimate") else "")
                         + f"; vs OpenFAST {OPENFAST_S} s: {OPENFAST_S / min(walls[k]):.1f}x.")
    text = "\n".join(rows) + "\n\n" + "\n".join(f"- {n}" for n in notes)
    text += (f"\n\nMachine load during the run (1-min load average on 2 cores): {os.getloadavg()[0]:.1f}; "
             f"{args.rounds} rounds, commands rotated each round.")
    print("\n" + text)
    if not args.no_write:
        write_section("startup", text)


if __name__ == "__main__":
    main()
