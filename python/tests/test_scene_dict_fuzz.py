"""Scene.from_dict under 400 mutated example scenes (scene_dict_fuzz.py, seed 1): every one converts or raises a
one-line ValueError; a crash, a RecursionError or another exception type fails (issue 47, item 6)."""
from scene_dict_fuzz import fuzz


def test_mutated_scenes_convert_or_raise_value_error():
    converted, refused = fuzz(iterations=400, seed=1)
    assert converted + refused == 400
    # Most mutations break a key the reader checks; some replace a value with one it accepts.
    assert refused > 200
