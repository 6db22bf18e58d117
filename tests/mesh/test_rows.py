"""unique_rows gives numpy's np.unique(axis=0) results, packed or not."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from vorobound.mesh.rows import KEY_LIMIT, row_keys, unique_rows

OPTIONS = [
    {},
    {"return_index": True},
    {"return_inverse": True},
    {"return_counts": True},
    {"return_index": True, "return_inverse": True, "return_counts": True},
]


def _same(rows: np.ndarray, options: dict) -> None:
    expected = np.unique(rows, axis=0, **options)
    found = unique_rows(rows, **options)
    if not options:
        assert found.dtype == rows.dtype
        np.testing.assert_array_equal(found, expected)
        return
    assert isinstance(found, tuple) and len(found) == len(expected)
    for mine, theirs in zip(found, expected, strict=True):
        np.testing.assert_array_equal(mine, np.asarray(theirs).reshape(mine.shape))
    assert found[0].dtype == rows.dtype


@settings(max_examples=60, deadline=None)
@given(
    rows=arrays(
        st.sampled_from([np.int32, np.int64]),
        st.tuples(st.integers(1, 40), st.integers(1, 4)),
        elements=st.integers(-(2**20), 2**20),
    ),
    option=st.sampled_from(OPTIONS),
)
def test_unique_rows_is_numpys_unique(rows, option):
    _same(rows, option)


@pytest.mark.parametrize("option", OPTIONS)
def test_wide_ranges_fall_back_to_numpy(option):
    # Two columns spanning 2⁶² each do not fit one key: numpy's own call answers.
    rows = np.array([[KEY_LIMIT, -KEY_LIMIT], [0, 1], [KEY_LIMIT, -KEY_LIMIT], [-5, 3]])
    _same(rows, option)


@pytest.mark.parametrize("option", OPTIONS)
def test_small_tables(option):
    _same(np.array([[3, 1, 2]]), option)
    _same(np.array([[0, 0], [0, 0]], dtype=np.int32), option)


@settings(max_examples=40, deadline=None)
@given(
    rows=arrays(
        np.int64, st.tuples(st.integers(1, 30), st.integers(1, 3)), elements=st.integers(-50, 50)
    )
)
def test_row_keys_sort_as_the_rows(rows):
    keys = row_keys(rows)
    assert keys is not None
    np.testing.assert_array_equal(np.argsort(keys, kind="stable"), np.lexsort(rows.T[::-1]))
    same = (rows[:, None, :] == rows[None, :, :]).all(axis=2)
    np.testing.assert_array_equal(keys[:, None] == keys[None, :], same)


def test_row_keys_refuse_what_does_not_fit():
    assert row_keys(np.array([[0, 0], [KEY_LIMIT, KEY_LIMIT]])) is None
    assert row_keys(np.zeros((3, 2))) is None  # not integers
