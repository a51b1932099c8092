"""wingmdao.utils.digest: equal arrays give equal digests, any change of value, shape or dtype another."""

import numpy as np

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
