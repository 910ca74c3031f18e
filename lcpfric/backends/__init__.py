"""Convex-solver backends (one module per solver); see :mod:`lcpfric.methods` for the registry."""
