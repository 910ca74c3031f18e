"""Figures for publication (journal column or page widths, 7 pt text, TrueType fonts, 300 dpi):
the house style (``style``), the hysteresis loop (``loop``), the continuum contacts' maps,
phase curves, zones and tractions (``contact``), and the half-space's stick/slip maps, traction
vectors and animations (``halfspace``). The paper's own figures are in :mod:`lcpfric.paper`.
Needs the ``plot`` extra (matplotlib)."""
