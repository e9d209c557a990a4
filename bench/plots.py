"""PNG plots of a benchmark run (matplotlib, Agg backend: no display needed).

Each function takes the raw data the measuring modules return and writes one file into
``out_dir``, returning its path (or None when there is nothing to draw).
"""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from jaka_driver.common.constants import SERVO_CYCLE  # noqa: E402

from .servo_latency import OBSERVED_P99_MS, observed_latency  # noqa: E402
from .state_topics import INTERARRIVAL_P99_MS  # noqa: E402


def _save(fig, ax, out_dir: Path, name: str) -> Path:
    """Legend, layout, write ``out_dir/name`` at 110 dpi, free the figure."""
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = out_dir / name
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def period_histogram(series: dict, out_dir: Path) -> Path | None:
    """``series``: label → receipt times (s) of ``joint_position``; inter-arrival histogram."""
    series = {k: v for k, v in series.items() if v is not None and len(v) > 2}
    if not series:
        return None
    fig, ax = plt.subplots(figsize=(8, 4.5))
    bins = np.arange(0.0, 30.5, 0.25)
    for label, recv in series.items():
        gaps = np.diff(recv) * 1e3
        ax.hist(np.clip(gaps, 0, 30), bins=bins, histtype="step", linewidth=1.4,
                label=f"{label} (p99 {np.percentile(gaps, 99):.1f} ms)")
    ax.axvline(SERVO_CYCLE * 1e3, color="grey", linestyle=":", label="8 ms period")
    ax.axvline(INTERARRIVAL_P99_MS, color="red", linestyle="--", label="p99 target 10 ms")
    ax.set_yscale("log")
    ax.set_xlabel("inter-arrival time of /jaka_driver/joint_position (ms; > 30 ms shown at 30)")
    ax.set_ylabel("messages")
    ax.set_title("State topic period as a subscriber sees it")
    return _save(fig, ax, out_dir, "period_histogram.png")


def servo_tracking(streams: dict, out_dir: Path, seconds: float = 2.0) -> Path | None:
    """``streams``: label → :func:`bench.servo_latency.sine_stream` result."""
    streams = {k: v for k, v in streams.items() if v is not None}
    if not streams:
        return None
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 7))
    first = next(iter(streams.values()))
    t0 = first["sent"][0]
    keep = first["sent"] <= t0 + seconds
    ax1.step(first["sent"][keep] - t0, first["targets"][keep, 0], where="post",
             label="servo_j target (at send time)")
    m = (first["stamp"] >= t0) & (first["stamp"] <= t0 + seconds)
    ax1.plot(first["stamp"][m] - t0, first["q"][m, 0], ".", markersize=3,
             label="joint_position (at sample stamp)")
    ax1.set_xlabel("time (s)")
    ax1.set_ylabel("joint_1 (rad)")
    ax1.set_title(f"servo_j sine streamed at 125 Hz — {next(iter(streams))}")
    ax1.legend(fontsize=8)
    bins = np.arange(0.0, 80.5, 1.0)
    for label, stream in streams.items():
        lat = observed_latency(stream)["latency_s"] * 1e3
        lat = lat[np.isfinite(lat)]
        if lat.size:
            ax2.hist(np.clip(lat, 0, 80), bins=bins, histtype="step", linewidth=1.4,
                     label=f"{label} (p99 {np.percentile(lat, 99):.1f} ms)")
    ax2.axvline(OBSERVED_P99_MS, color="red", linestyle="--", label="p99 target 16 ms")
    ax2.set_xlabel("command → first joint_position sample that reached it (ms)")
    ax2.set_ylabel("targets")
    return _save(fig, ax2, out_dir, "servo_tracking.png")


def linear_deviation(lines: list, out_dir: Path, target_mm: float) -> Path | None:
    """Deviation from the ideal line along each linear_move, against path fraction."""
    lines = [ln for ln in lines if ln.get("ret") == 1 and len(ln.get("deviation_mm", [])) > 0]
    if not lines:
        return None
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for ln in lines:
        order = np.argsort(ln["fraction"])
        ax.plot(ln["fraction"][order], ln["deviation_mm"][order] * 1e3, linewidth=0.9)
    ax.axhline(target_mm * 1e3, color="red", linestyle="--", label=f"target {target_mm:g} mm")
    ax.set_yscale("symlog", linthresh=1.0)
    ax.set_xlabel("fraction of the line")
    ax.set_ylabel("TCP distance from the ideal line (µm)")
    ax.set_title(f"linear_move at 100 mm/s on the twin: {len(lines)} lines")
    return _save(fig, ax, out_dir, "linear_deviation.png")


def ik_times(results: list, out_dir: Path) -> Path | None:
    """Per-call IK time distributions, ours and KDL's, every model."""
    if not results:
        return None
    data, labels = [], []
    for r in results:
        data += [r["ours_us"], r["kdl_us"]]
        labels += [f"{r['model']}\nours", f"{r['model']}\nKDL"]
    fig, ax = plt.subplots(figsize=(max(8.0, 0.4 * len(data)), 4.5))   # 22 models: 44 boxes
    ax.boxplot(data, showfliers=False)
    ax.set_xticks(range(1, len(labels) + 1), labels, fontsize=7)
    ax.axhline(50, color="red", linestyle="--", label="median target 50 µs")
    ax.set_ylabel("time per IK call (µs; whiskers 1.5 IQR)")
    ax.set_title("IK: ours vs PyKDL ChainIkSolverPos_NR_JL, same targets")
    return _save(fig, ax, out_dir, "ik_times.png")
