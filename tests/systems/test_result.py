"""What a workflow returns: flat numbers and progress stages."""
import numpy as np

from salkit.systems.result import flat_numbers, stage


def test_flat_numbers_keeps_plain_numbers():
    d = {"a": np.float32(1.5), "b": np.int64(3), "c": np.bool_(True), "d": [1, 2], "_e": 1.0}
    out = flat_numbers(d)
    assert out == {"a": 1.5, "b": 3, "c": 1} and type(out["a"]) is float and type(out["b"]) is int


def test_stage_names_the_unit():
    seen = []
    stage(lambda *a: seen.append(a), "pulses")(3, 10)
    assert seen == [("pulses", 3, 10)] and stage(None, "x") is None
