"""A prototype's figure: matplotlib without a window, and the PNG written whole or not
at all (to NAME.partial.png beside it, then renamed), so that a book build never picks
up half a picture."""

from __future__ import annotations

import os


def new_figure(**options):
    """plt.figure(**options) on the Agg backend: no display needed."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt.figure(**options)


def save_figure_file(figure, path) -> None:
    """Lays the figure out, writes it to `path` as PNG atomically, and closes it."""
    import matplotlib.pyplot as plt
    figure.tight_layout()
    partial = f"{path}.partial.png"
    figure.savefig(partial, format="png")
    plt.close(figure)
    os.replace(partial, path)
