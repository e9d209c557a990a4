"""The benchmark report: rows of (metric, value, target, result, note), written as
``latest.json`` (every number, for tools) and ``latest.md`` (the table, for people)."""
from __future__ import annotations

import json
import platform
import subprocess
from dataclasses import asdict, dataclass, field
from pathlib import Path

PASS, FAIL, REPORT, NOT_RUN = "pass", "FAIL", "report", "not run"


@dataclass
class Bound:
    """One number a target judges and the limit it must keep: ``value`` ≤ ``limit``
    (``at_most``) or ≥ it, in ``unit``; ``what`` names the number when it is not plain from the
    row ("p99", "above the floor"). A row's several bounds must all hold."""

    value: float
    limit: float
    unit: str = ""
    at_most: bool = True
    what: str = ""

    @property
    def margin(self) -> float:
        """How far the value sits inside its limit (negative: outside), in ``unit``."""
        return self.limit - self.value if self.at_most else self.value - self.limit

    @property
    def met(self) -> bool:
        return self.margin >= 0

    @property
    def sense(self) -> str:
        return "≤" if self.at_most else "≥"


def at_most(value, limit: float, unit: str = "", what: str = "") -> list[Bound]:
    """``[Bound]`` for "``value`` ≤ ``limit``", or ``[]`` when there is no value to judge."""
    return [] if value is None else [Bound(float(value), float(limit), unit, True, what)]


def at_least(value, limit: float, unit: str = "", what: str = "") -> list[Bound]:
    """``[Bound]`` for "``value`` ≥ ``limit``", or ``[]`` when there is no value to judge."""
    return [] if value is None else [Bound(float(value), float(limit), unit, False, what)]


@dataclass
class Row:
    """One line of the table. ``status`` is :data:`PASS`, :data:`FAIL`, :data:`REPORT` (no
    target: the number is the deliverable) or :data:`NOT_RUN`. ``note`` says, for a miss, why
    and what would fix it; for a row not run, why not. ``data`` keeps the raw numbers;
    ``bounds`` the numbers its target judges, each with its limit (a run of several
    repetitions reports their spread and margins: :mod:`bench.runs`)."""

    group: str
    metric: str
    value: str
    target: str
    status: str
    note: str = ""
    data: dict = field(default_factory=dict)
    bounds: list = field(default_factory=list)


def judged(ok: bool) -> str:
    return PASS if ok else FAIL


def not_run(group: str, metric: str, target: str, reason: str) -> Row:
    return Row(group, metric, "—", target, NOT_RUN, reason)


def _machine() -> dict:
    import os
    info = {"python": platform.python_version(), "cpus": os.cpu_count(),
            "kernel": platform.release()}
    try:
        info["cpu"] = next(line.split(":", 1)[1].strip() for line in
                           open("/proc/cpuinfo") if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return info


def _commit(root: Path) -> str:
    """The checkout's commit, ``-dirty`` if a tracked file differs from it — the results this
    run has just written (plots first) aside, or every run would read dirty."""
    git = ["git", "-C", str(root)]
    try:
        commit = subprocess.run(git + ["describe", "--always"], capture_output=True, text=True,
                                timeout=5).stdout.strip()
        changed = subprocess.run(git + ["status", "--porcelain", "--untracked-files=no", "--",
                                        ".", ":(exclude)bench/results"],
                                 capture_output=True, text=True, timeout=5).stdout.strip()
        return f"{commit}-dirty" if commit and changed else commit
    except (OSError, subprocess.SubprocessError):
        return ""


def write(rows: list[Row], out_dir: Path, root: Path, started: str, duration_s: float,
          plots: list[str], extra: dict, quick: bool = False, runs: int = 1) -> tuple[Path, Path]:
    """Write ``latest.json`` and ``latest.md`` into ``out_dir``; returns their paths.
    ``extra`` may hold ``machine_percent_before`` / ``machine_percent_during`` (whole-machine
    CPU, % of one core), printed in the header so a disturbed run shows it. ``runs`` > 1:
    ``rows`` are :func:`bench.runs.combine`'s, and the table gives each row's spread over the
    runs, its margin in the worst run and the runs that met its target."""
    out_dir.mkdir(parents=True, exist_ok=True)
    meta = {"started": started, "duration_s": round(duration_s, 1), "commit": _commit(root),
            "machine": _machine(), "quick": quick, "runs": runs,
            "run_seconds": extra.get("run_seconds"),
            "machine_percent_before": extra.get("machine_percent_before"),
            "machine_percent_during": extra.get("machine_percent_during", {}),
            "other_programs": extra.get("other_programs", [])}
    doc = {**meta, "rows": [asdict(r) for r in rows], "plots": plots, "extra": extra}
    json_path = out_dir / "latest.json"
    json_path.write_text(json.dumps(doc, indent=1, default=_plain) + "\n")
    md_path = out_dir / "latest.md"
    md_path.write_text(_markdown(rows, meta, plots))
    return json_path, md_path


def _plain(value):
    """numpy scalars and arrays → JSON."""
    if hasattr(value, "tolist"):
        return value.tolist()
    raise TypeError(f"cannot serialise {type(value).__name__}")


def _load_lines(meta: dict) -> list[str]:
    """The machine's own load around the run: other programs disturb every timing row."""
    lines = []
    if meta.get("quick"):
        lines += ["**Quick smoke run (`--quick`): short windows, not the benchmark.**", ""]
    before = meta.get("machine_percent_before")
    during = {k: v for k, v in (meta.get("machine_percent_during") or {}).items()
              if v is not None}
    if before is not None:
        text = (f"Whole-machine CPU use, % of one core (200 % = both cores): {before:.0f} % "
                "in the second before the run")
        if during:
            listed = ", ".join(f"{k} {v:.0f} %" for k, v in during.items())
            text += (f"; during the idle state-topic windows {listed} (node, emulator and "
                     "this benchmark included)")
        lines += [text + ".", ""]
    others = meta.get("other_programs") or []
    if others:
        lines += ["**Other programs used the CPU through the whole run** (they disturb every "
                  "timing row; rerun on a quiet machine to compare): " + "; ".join(
                      f"`{p['command'][:70]}` {p['cpu_percent']:.0f} %" for p in others[:6])
                  + ".", ""]
    return lines


def _cell(text: str) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def _markdown(rows: list[Row], meta: dict, plots: list[str]) -> str:
    from .runs import markdown_row
    m = meta["machine"]
    runs = meta.get("runs", 1)
    counts = {s: sum(r.status == s for r in rows) for s in (PASS, FAIL, REPORT, NOT_RUN)}
    if runs > 1:
        took = meta.get("run_seconds") or []
        how = (f"**{runs} runs** of the same groups, one after the other"
               + (f" ({', '.join(f'{s:.0f}' for s in took)} s)" if took else "")
               + ": each row's value is its judged number's min / median / max over the runs, "
               "its margin the room left to the target in the worst run (negative: a miss), "
               "and it passes only if it passed in every run.")
        head = ["| metric | min / median / max | target | margin, worst run | runs met | "
                "result |", "|---|---|---|---|---|---|"]
    else:
        how = ""
        head = ["| metric | value | target | result |", "|---|---|---|---|"]
    lines = [
        "# jaka_driver benchmarks",
        "",
        f"Run {meta['started']} on commit `{meta['commit']}`, {m.get('cpus')} CPUs "
        f"({m.get('cpu', '?')}), Python {m['python']}; took {meta['duration_s']:.0f} s "
        "(`make bench`).",
        "",
        *_load_lines(meta),
        *([how, ""] if how else []),
        f"**{counts[PASS]} pass, {counts[FAIL]} fail, {counts[REPORT]} reported without a "
        f"target, {counts[NOT_RUN]} not run.** Targets are those written in `bench/` and are never "
        "moved; a miss is explained below the table.",
        "",
        *head,
    ]
    notes = []
    group = None
    for r in rows:
        if r.group != group:
            group = r.group
            lines.append(f"| **{_cell(group)}** |" + " |" * (5 if runs > 1 else 3))
        mark = r.status
        if r.note and r.status in (FAIL, NOT_RUN):
            notes.append((r, len(notes) + 1))
            mark = f"{r.status} [{len(notes)}]"
        if runs > 1:
            lines.append(markdown_row(r, mark, _cell))
        else:
            lines.append(f"| {_cell(r.metric)} | {_cell(r.value)} | {_cell(r.target)} | "
                         f"{mark} |")
    if notes:
        lines += ["", "## Why a target is missed, and what would fix it", ""]
        for r, k in notes:
            lines.append(f"{k}. **{r.metric}** — {r.note}")
    info = [r for r in rows if r.note and r.status in (PASS, REPORT)]
    if info:
        lines += ["", "## Notes", ""]
        lines += [f"- **{r.metric}** — {r.note}" for r in info]
    if plots:
        lines += ["", "## Plots", ""]
        lines += [f"![{Path(p).stem}]({Path(p).name})" for p in plots]
    return "\n".join(lines) + "\n"
