"""The plot of a run (OUT/benchmark.png): whole-process times at fixed samples per pixel, times to a clean image,
and whitted's rays per second; a bar per driver beside POV-Ray's, labelled with POV-Ray's time over whitted's."""
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after the back end is chosen)
from matplotlib.ticker import FuncFormatter, LogLocator  # noqa: E402

from .measures import by_scene_and_size  # noqa: E402
from .plan import PSNR_TARGET_DB  # noqa: E402

COLOURS = ["#1f5fa8", "#6aa84f", "#8e44ad", "#17becf"]
POV_COLOUR = "#d9822b"


class Bars:
    """Where the bars of one group stand: one per driver, then POV-Ray's."""

    def __init__(self, labels):
        self.n = len(labels) + 1
        self.width = 0.8 / self.n

    def offset(self, i):
        return (i - self.n / 2 + 0.5) * self.width


def plot(documents, path):
    """Draws every driver's document into one figure at `path` (written whole, through a temporary file)."""
    labels = list(documents)
    first = documents[labels[0]]
    fixed = [(r["scene"], r["size"], r["width"], r["height"], r["spp"]) for r in first["results"]]
    eq = [(r["scene"], r["width"], r["height"]) for r in first["equal_quality"]]
    panels = [(draw, rows, legend) for draw, rows, legend in ((plot_fixed, fixed, "upper left"),
                                                             (plot_equal_quality, eq, "upper left"),
                                                             (plot_rays, fixed, "best")) if rows]
    fig, axes = plt.subplots(len(panels), 1, figsize=(max(8, 1.6 * max(len(fixed), len(eq), 1)), 3.6 * len(panels)))
    axes = list(axes) if len(panels) > 1 else [axes]
    for ax, (draw, rows, legend) in zip(axes, panels):
        draw(ax, documents, rows, Bars(labels))
        ax.legend(fontsize=7, loc=legend)
    fig.tight_layout()
    temporary = path + ".partial.png"
    fig.savefig(temporary, dpi=80)
    os.replace(temporary, path)


def log_axis(ax, values):
    """A logarithmic time axis with room for the labels above the bars."""
    ax.set_yscale("log")
    ax.yaxis.set_major_locator(LogLocator(subs=(1, 2, 5)))
    ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    ax.yaxis.set_minor_formatter(plt.NullFormatter())
    positive = [v for v in values if v]
    if positive:
        ax.set_ylim(min(positive) / 2, max(positive) * 6)  # room for the labels above the bars


def fixed_ticks(ax, fixed):
    """The x axis of the fixed-spp panels: scene, size and samples per pixel."""
    ax.set_xticks(list(range(len(fixed))))
    ax.set_xticklabels([f"{s}\n{w}x{h} {spp} spp" for s, _, w, h, spp in fixed], fontsize=8)


def plot_fixed(ax, documents, fixed, bars):
    """Whole-process time at fixed samples per pixel."""
    labels = list(documents)
    rows = {label: by_scene_and_size(documents[label]["results"]) for label in labels}
    values = []
    for k, (s, z, *_) in enumerate(fixed):
        pov = (rows[labels[0]][(s, z)]["povray"] or {}).get("wall_s")
        mine = [rows[label][(s, z)]["whitted"]["wall_s"] for label in labels]
        values += mine + [pov]
        for i, v in enumerate(mine):
            ax.bar(k + bars.offset(i), v, bars.width, color=COLOURS[i % len(COLOURS)],
                   label=f"whitted, {labels[i]}" if k == 0 else None)
            if pov:
                ax.text(k + bars.offset(i), v * 1.1, f"{pov / v:.2g}x", ha="center", fontsize=7)
        if pov:
            ax.bar(k + bars.offset(bars.n - 1), pov, bars.width, color=POV_COLOUR,
                   label="POV-Ray 3.7 (+WT2)" if k == 0 else None)
    fixed_ticks(ax, fixed)
    ax.set_title(f"fixed samples per pixel (whitted --aa uniform; POV-Ray -A or +A0.0 +AM1), whole process\n"
                 "label = POV-Ray time / whitted time", fontsize=9)
    ax.set_ylabel("seconds")
    log_axis(ax, values)


def povray_clean_time(pov):
    """POV-Ray's time to a clean image and its threshold; its last try, marked, when it reached none."""
    if pov["time_to_clean_s"]:
        return pov["time_to_clean_s"], f"+A{pov['reached_threshold']}"
    return pov["tries"][-1]["wall_s"], f"+A{pov['tries'][-1]['threshold']}: <50 dB"


def plot_equal_quality(ax, documents, eq, bars):
    """Time to a clean image; hatched where the target was not reached."""
    labels = list(documents)
    rows = {label: {r["scene"]: r for r in documents[label]["equal_quality"]} for label in labels}
    values = []
    for k, (s, *_) in enumerate(eq):
        pov = rows[labels[0]][s]["povray"]
        pov_time, pov_note = povray_clean_time(pov) if pov and pov["tries"] else (None, None)
        for i, label in enumerate(labels):
            mine = rows[label][s]["whitted"]
            if mine["time_to_clean_s"]:
                v, note = mine["time_to_clean_s"], mine["tries"][mine["reached"]]["sampling"]
            else:
                v, note = mine["tries"][-1]["wall_s"], "<50 dB"
            values.append(v)
            ax.bar(k + bars.offset(i), v, bars.width, color=COLOURS[i % len(COLOURS)],
                   hatch=None if mine["time_to_clean_s"] else "//",
                   label=f"whitted, {label}" if k == 0 else None)
            text = note if note != "default" else ""
            if pov_time:
                text = f"{pov_time / v:.2g}x" + (f"\n{text}" if text else "")
            ax.text(k + bars.offset(i), v * 1.1, text, ha="center", fontsize=7)
        if pov_time:
            values.append(pov_time)
            ax.bar(k + bars.offset(bars.n - 1), pov_time, bars.width, color=POV_COLOUR,
                   hatch=None if pov["time_to_clean_s"] else "//",
                   label="POV-Ray +AM2 +R3, first threshold reaching 50 dB" if k == 0 else None)
            ax.text(k + bars.offset(bars.n - 1), pov_time * 1.1, pov_note, ha="center", fontsize=7)
    ax.set_xticks(list(range(len(eq))))
    ax.set_xticklabels([f"{s}\n{w}x{h}" for s, w, h in eq], fontsize=8)
    ax.set_title(f"time to a clean image (>= {PSNR_TARGET_DB:.0f} dB against the renderer's own 64-sample "
                 "uniform image), whole process\nlabel = POV-Ray / whitted time; hatched: 50 dB not reached "
                 "(last try shown)", fontsize=9)
    ax.set_ylabel("seconds")
    log_axis(ax, values)


def plot_rays(ax, documents, fixed, bars):
    """whitted's rays per second at fixed samples per pixel, a bar per driver."""
    labels = list(documents)
    rows = {label: by_scene_and_size(documents[label]["results"]) for label in labels}
    first = documents[labels[0]]
    for i, label in enumerate(labels):
        ax.bar([k + (i - len(labels) / 2 + 0.5) * bars.width for k in range(len(fixed))],
               [rows[label][(s, z)]["whitted"]["rays_per_s"] / 1e6 for s, z, *_ in fixed], bars.width,
               color=COLOURS[i % len(COLOURS)], label=f"{label}: {documents[label]['driver']}")
    fixed_ticks(ax, fixed)
    ax.set_title(f"whitted rays per second (shader counts: primary + shadow + secondary) on "
                 f"{first['cpu_model']}, {first['cpus']} CPUs", fontsize=9)
    ax.set_ylabel("Mrays/s")
