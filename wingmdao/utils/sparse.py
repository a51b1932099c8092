"""Small sparse-matrix helpers shared by the time march and the OpenMDAO components."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp


def scatter_matrix(index, size):
    """The selection matrix of ``index``: row k picks column ``index[k]`` (its transpose sums
    entries into slots).

    Parameters
    ----------
    index : sequence of int
        Column picked by each row.
    size : int
        Number of columns.

    Returns
    -------
    scipy.sparse.csr_matrix, shape (len(index), size)
        A one at (k, index[k]), zeros elsewhere.
    """
    m = len(index)
    return sp.csr_matrix((np.ones(m), (np.arange(m), index)), shape=(m, size))
