"""wingmdao.utils.digest: equal arrays give equal digests, any change of value, shape or dtype another."""

import numpy as np
import pytest

from wingmdao.utils.digest import array_digest


def test_digest_recognises_equal_arrays_and_changes():
    rng = np.random.default_rng(2)
    a = rng.normal(size=(40, 9))
    assert array_digest(a) == array_digest(a.copy())
    assert array_digest(a.T) == array_digest(np.ascontiguousarray(a.T))   # C order of the values
    b = a.copy()
    b[17, 3] = np.nextafter(b[17, 3], 1.0)   # one ulp
    assert array_digest(b) != array_digest(a)
    assert array_digest(a.reshape(9, 40)) != array_digest(a)
    assert array_digest(a.astype(np.float32)) != array_digest(a.astype(np.float32).astype(float))
    assert array_digest(np.zeros(0)) == array_digest(np.zeros(0)) and array_digest(np.float64(2.0)) == array_digest(2.0)


@pytest.mark.parametrize("size", [360, 400_000])     # below and above COPY_BELOW_BYTES (a copy, a digest)
def test_stamp_matches_exactly_the_same_bits(size):
    from wingmdao.utils.digest import COPY_BELOW_BYTES, ArrayStamp

    a = np.random.default_rng(3).normal(size=size)
    stamp = ArrayStamp(a)
    assert (stamp._copy is None) == (a.nbytes > COPY_BELOW_BYTES)
    assert stamp.matches(a) and stamp.matches(a.copy())
    b = a.copy()
    b[size // 2] = np.nextafter(b[size // 2], np.inf)   # one ulp
    assert not stamp.matches(b)
    z = np.zeros(size)
    assert not ArrayStamp(z).matches(-z)                   # equal values, other bits
    assert not stamp.matches(a.reshape(-1, 2)) and not stamp.matches(a.astype(np.float32))
    a[0] += 1.0                                            # the stamp does not follow the array
    assert not stamp.matches(a)
