"""What a program can check in a picture (used by tests/test_paper.py for the figures of
`bkwaves paper --quick`, tests/test_plot_readable.py for every picture `bkwaves plot` draws
of the example runs and sweeps, and tests/test_plot_run.py)."""

import numpy as np


def _overlaps(boxes) -> bool:
    return any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1 :])


def figure_problems(fig) -> list[str]:
    """What a program can check in a figure: every axes with its axis labels (a colorbar
    with one, or a title), a legend wherever an axes holds more than one labelled series,
    tick labels that do not overlap, and marker data inside the axes limits."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    problems = []
    for n, ax in enumerate(fig.axes):
        if not ax.axison:
            continue
        where = f"axes {n} ({ax.get_title() or ax.get_label()})"
        if ax.get_label() == "<colorbar>":
            if not (ax.get_ylabel() or ax.get_xlabel() or ax.get_title()):
                problems.append(f"{where}: colorbar without a label")
            continue
        # a twin axes (twinx, twiny) shares one axis, and its label, with its sibling
        xs = ax.get_shared_x_axes().get_siblings(ax)
        ys = ax.get_shared_y_axes().get_siblings(ax)
        if not any(a.get_xlabel() for a in xs) or not any(a.get_ylabel() for a in ys):
            problems.append(f"{where}: an axis without a label")
        labelled = [
            a
            for a in (*ax.lines, *ax.collections, *ax.patches, *ax.containers)
            if not str(a.get_label()).startswith("_")
        ]
        if len(labelled) > 1 and ax.get_legend() is None and not fig.legends:
            problems.append(f"{where}: {len(labelled)} labelled series and no legend")
        for axis in (ax.xaxis, ax.yaxis):
            lo, hi = sorted(axis.get_view_interval())
            boxes = [
                t.get_window_extent(renderer)
                for loc, t in zip(axis.get_majorticklocs(), axis.get_majorticklabels(), strict=True)
                if lo <= loc <= hi and t.get_visible() and t.get_text()
            ]
            minor = [
                t.get_window_extent(renderer)
                for loc, t in zip(axis.get_minorticklocs(), axis.get_minorticklabels(), strict=True)
                if lo <= loc <= hi and t.get_visible() and t.get_text()
            ]
            if _overlaps(boxes + minor):
                problems.append(f"{where}: overlapping tick labels on {axis.axis_name}")
        (x0, x1), (y0, y1) = sorted(ax.get_xlim()), sorted(ax.get_ylim())
        for line in ax.lines:
            if line.get_transform() != ax.transData or line.get_linestyle() not in ("None", ""):
                continue  # reference lines and curves may run past the frame; markers not
            x, y = (np.asarray(v, float) for v in line.get_data())
            ok = np.isfinite(x) & np.isfinite(y)
            if not np.all((x[ok] >= x0) & (x[ok] <= x1) & (y[ok] >= y0) & (y[ok] <= y1)):
                problems.append(f"{where}: markers of {line.get_label()!r} outside the axes")
    return problems
