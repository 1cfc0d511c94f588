"""The print-size measure of the figures' tests: every text of a rendered figure, printed one
column of a paper wide (3.5 in), is at least 9 pt: ``font size × COLUMN / figure width ≥ SMALLEST``."""
from __future__ import annotations

#: one column of a paper (inches) and the smallest text it may print (points)
COLUMN, SMALLEST = 3.5, 9.0


def printed_points(fig) -> list[tuple[float, str]]:
    """Every visible, non-empty text of the rendered ``fig`` with its size (points) when the figure
    is printed one column wide: ``size × COLUMN / width``."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.text import Text

    if not isinstance(fig.canvas, FigureCanvasAgg):
        FigureCanvasAgg(fig)
    fig.canvas.draw()
    width = fig.get_size_inches()[0]
    return [(t.get_fontsize() * COLUMN / width, t.get_text()) for t in fig.findobj(Text)
            if t.get_visible() and t.get_text().strip()]


def assert_printable(fig):
    sizes = printed_points(fig)
    assert sizes, "no text found"
    small = [(round(p, 2), text) for p, text in sizes if p < SMALLEST - 1e-9]
    assert not small, f"texts under {SMALLEST} pt at one column: {small[:5]}"
