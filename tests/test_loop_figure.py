"""The loop figure at its printed size: tick labels that never run into each other, whatever the
magnitudes (a power of ten goes into the axis label, never into an offset text), and axis labels
that name the units of a dimensional node and the normalized quantities of a normalized one
(issue 35)."""

import pytest

from lcpfric import SingleNode, steady_state
from lcpfric.analysis.loop import hysteresis_loop
from lcpfric.figures.loop import figure_loop, loop_labels

from support import need_modules

NODES = {
    # the case: v ~ 2e-4, F ~ 100
    "dimensional": SingleNode(k11=1e6, f=0.3, P0=100.0, P1=300.0, Q1=200.0, phi=1.5708),
    "huge forces": SingleNode(k11=3.0, f=0.7, P0=4e7, P1=3e7, Q1=8e7, phi=2.0),
    "offset datum": SingleNode(k11=1e3, f=0.3, P0=1.0, P1=0.5, Q1=2.0, phi=1.0, Q0=1234.5),
    "normalized": SingleNode.normalized(P1=1.5, Q1=2.0, phi=1.885),
    "normalized, large": SingleNode.normalized(P1=40.0, Q1=9e4, phi=0.3),
}


def overlap(fig, axis) -> bool:
    """Whether two of the drawn figure's tick labels on ``axis`` overlap."""
    boxes = [t.get_window_extent() for t in axis.get_ticklabels() if t.get_text()]
    lo, hi = ("x0", "x1") if axis.axis_name == "x" else ("y0", "y1")
    boxes.sort(key=lambda b: getattr(b, lo))
    return any(getattr(a, hi) > getattr(b, lo) for a, b in zip(boxes, boxes[1:]))


@pytest.mark.parametrize("case", list(NODES))
def test_tick_labels_never_collide(case):
    need_modules("matplotlib")
    node = NODES[case]
    names, units = loop_labels(node)
    fig = figure_loop(hysteresis_loop(steady_state(node, "exact", 100)), "t", units, names)
    ax = fig.axes[0]
    fig.draw_without_rendering()
    for axis in (ax.xaxis, ax.yaxis):
        assert not overlap(fig, axis), axis.axis_name
        assert len([t for t in axis.get_ticklabels() if t.get_text()]) >= 2
        assert not axis.get_offset_text().get_visible()
    xlabel, ylabel = ax.get_xlabel(), ax.get_ylabel()
    if node.dimensional:
        assert xlabel.endswith("load / k11 units]") and ylabel.endswith("load units]")
    else:
        assert "(fP_0)" in xlabel and "(fP_0)" in ylabel
    assert "[force]" not in ylabel and "[displacement]" not in xlabel
    if case == "dimensional":
        assert "10$^{-4}$" in xlabel and "10$" not in ylabel
    if case == "huge forces":
        assert "10$^{7}$" in ylabel


def test_units_given_by_hand():
    need_modules("matplotlib")
    node = NODES["dimensional"]
    fig = figure_loop(hysteresis_loop(steady_state(node, "exact", 100)), units=("m", "N"))
    assert fig.axes[0].get_xlabel() == "tangential displacement v [10$^{-4}$ m]"
    assert fig.axes[0].get_ylabel() == "friction force F [N]"
