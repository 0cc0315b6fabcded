"""Array types of the core's signatures (physics, monitor): float64 arrays and what broadcasts with them."""

from __future__ import annotations

from typing import Any, TypeAlias

import numpy as np
import numpy.typing as npt

#: float64 array of any shape (SI values, units named where it is used)
FloatArray: TypeAlias = npt.NDArray[np.float64]
#: integer array of any shape (indices, counts, ns stamps)
IntArray: TypeAlias = npt.NDArray[np.signedinteger[Any]]
#: boolean mask of any shape
BoolArray: TypeAlias = npt.NDArray[np.bool_]
#: a scalar or an array of them: the vectorised physics broadcasts both elementwise
Floats: TypeAlias = float | FloatArray
