"""Convex-solver backends, one module per solver (see :mod:`lcpfric.methods` for the registry).

Every increment is the maximum-dissipation projection of the trial force onto the friction cone
in the metric of K⁻¹, problem (P); :mod:`lcpfric.backends._problem` derives it and holds what the
backends share (the problems of the contact sets, the residual checks, the active-set
refinement, the stepper). Each backend module adds only the calls to its solver:

``clarabel_``   Clarabel's direct API, updated in place each step (d = 1 and 2)
``osqp_``       OSQP, set up once, updated and warm-started each step (d = 1)
``qpsolvers_``  any solver qpsolvers has installed (d = 1)
``cvxpy_``      one DPP-parametrized cvxpy problem per contact set (d = 2 with conic solvers)
"""
