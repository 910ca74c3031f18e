"""The linear algebra of the steppers: blocks of K updated as a set changes
(:mod:`.blocks`), the compliance known by its products (:mod:`.operator`), the pattern update of
box-constrained problems (:mod:`.patterns`) and conjugate gradients (:mod:`.cg`)."""

from .blocks import BandedBlock, DenseBlock, SparseBlock, make_block
from .operator import OperatorBlock
from .patterns import PatternUpdate

__all__ = [
    "DenseBlock",
    "BandedBlock",
    "SparseBlock",
    "make_block",
    "OperatorBlock",
    "PatternUpdate",
]
