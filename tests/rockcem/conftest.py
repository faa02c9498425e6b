"""Shared fixtures of the rockcem tests."""

import pytest


@pytest.fixture
def drawn(monkeypatch):
    """The figures `rockcem plot` would save, kept open for inspection (closed afterwards)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rockcem import plots

    figures = []

    def keep(fig, path, **_):
        figures.append(fig)
        return path

    monkeypatch.setattr(plots, "save_figure", keep)
    yield figures
    plt.close("all")
