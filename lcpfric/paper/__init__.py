"""The founding paper's material: its quantitative claims recomputed, its figures, and its
motor example.

``claims``   every quantitative statement of the paper, recomputed (``lcpfric paper-claims``)
``figures``  Figs. 3-7 and 9 for publication (``lcpfric figures``)
``motor``    the motor-mount example of Section 5 (Fig. 9)
"""
