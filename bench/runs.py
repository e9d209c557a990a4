"""Several runs of the same benchmarks as one table (``python -m bench --runs N``): each
targeted row's judged numbers as min / median / max over the runs, its margin to its target in
the worst run, and a result that is pass only if the row passed in every run — never judged on
the median. Targets are the rows' own (:class:`~bench.report.Bound`); nothing here moves one.
"""
from __future__ import annotations

import statistics
from dataclasses import asdict

from .report import FAIL, NOT_RUN, PASS, REPORT, Row


def combine(runs: list[list[Row]]) -> list[Row]:
    """One row per row of the runs (matched by group, metric and their order among equal
    ones), in the order they first appear. Its ``value`` gives the spread of each of its
    bounds (or each run's value, for a row without bounds), ``data["spread"]`` the numbers,
    ``data["runs"]`` each run's row (None where a run had no such row)."""
    order: list[tuple] = []
    table: dict[tuple, list] = {}
    for k, rows in enumerate(runs):
        seen: dict[tuple, int] = {}
        for row in rows:
            base = (row.group, row.metric)
            key = base + (seen.get(base, 0),)
            seen[base] = key[2] + 1
            if key not in table:
                table[key] = [None] * len(runs)
                order.append(key)
            table[key][k] = row
    return [_combined(table[key]) for key in order]


def status_over_runs(statuses: list) -> str:
    """A row's result over the runs: FAIL if it failed in any; pass only if it passed in every
    one; report if it is reported in every one; else not run (missing or not run in some)."""
    if FAIL in statuses:
        return FAIL
    if all(s == PASS for s in statuses):
        return PASS
    if all(s == REPORT for s in statuses):
        return REPORT
    return NOT_RUN


def spread(rows: list) -> list[dict]:
    """Per bound (by position) over the runs that have it: the limit, the values' min /
    median / max and the worst run's margin (the smallest: negative is a miss)."""
    out = []
    width = max((len(r.bounds) for r in rows if r is not None), default=0)
    for i in range(width):
        bounds = [r.bounds[i] for r in rows if r is not None and len(r.bounds) > i]
        values = [b.value for b in bounds]
        first = bounds[0]
        limits = sorted({b.limit for b in bounds})
        out.append({"what": first.what, "unit": first.unit, "sense": first.sense,
                    "limit": limits[0] if len(limits) == 1 else limits,
                    "values": values, "min": min(values),
                    "median": statistics.median(values), "max": max(values),
                    "worst_margin": min(b.margin for b in bounds),
                    "margins": [b.margin for b in bounds], "runs": len(bounds)})
    return out


def num(x: float) -> str:
    """A value for the table: 4 significant digits, no exponent for everyday sizes."""
    return f"{x:.4g}"


def margin_text(s: dict) -> str:
    """``+0.12 ms`` (room to spare) or ``−0.5 ms`` (a miss) for one bound's worst run."""
    m = s["worst_margin"]
    sign = "+" if m >= 0 else "−"
    return f"{sign}{num(abs(m))} {s['unit']}".strip()


def _combined(rows: list) -> Row:
    n = len(rows)
    present = [r for r in rows if r is not None]
    first = present[0]
    statuses = [r.status if r is not None else NOT_RUN for r in rows]
    status = status_over_runs(statuses)
    spreads = spread(rows)
    met = sum(s == PASS for s in statuses)
    if spreads:
        value = "; ".join(
            f"{s['what'] + ' ' if s['what'] else ''}{num(s['min'])} / {num(s['median'])} / "
            f"{num(s['max'])} {s['unit']}".rstrip() for s in spreads)
        if any(s["runs"] < n for s in spreads):
            value += f" ({min(s['runs'] for s in spreads)} of {n} runs)"
    else:
        value = " ‖ ".join(f"run {k + 1}: {r.value if r is not None else '—'}"
                           for k, r in enumerate(rows))
    notes = []
    for k, r in enumerate(rows):
        if r is None:
            notes.append(f"run {k + 1}: no such row")
        elif r.status in (FAIL, NOT_RUN) and r.note:
            notes.append(f"run {k + 1}: {r.note}")
    if status in (PASS, REPORT) and first.note:
        notes = [first.note]
    return Row(first.group, first.metric, value, first.target, status, " ".join(notes),
               data={"spread": spreads, "met_in": met, "of_runs": n,
                     "runs": [asdict(r) if r is not None else None for r in rows]})


def markdown_row(r: Row, mark: str, cell) -> str:
    """The table line of a combined row: metric, min / median / max, target, margin in the
    worst run, runs in which the target was met, result."""
    spreads = r.data.get("spread", [])
    margins = "; ".join(margin_text(s) for s in spreads) or "—"
    met = (f"{r.data['met_in']} of {r.data['of_runs']}"
           if r.status != REPORT and "met_in" in r.data else "—")
    return (f"| {cell(r.metric)} | {cell(r.value)} | {cell(r.target)} | {cell(margins)} | "
            f"{met} | {mark} |")
