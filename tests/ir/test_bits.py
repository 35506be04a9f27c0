"""``bits``: the set-bit indices of a fact mask, ascending, for small and large masks."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from stampc.ir.grounded import bits


@settings(max_examples=300, deadline=None)
@given(st.lists(st.integers(min_value=0, max_value=70_000), max_size=40))
def test_bits_lists_exactly_the_set_bits_in_ascending_order(indices):
    mask = 0
    for i in indices:
        mask |= 1 << i
    assert list(bits(mask)) == sorted(set(indices))


def test_bits_of_a_large_sparse_mask_beyond_the_fuzzed_range():
    """1,000 bits spread over 200,000 (the text-scan branch, far above its threshold)."""
    indices = list(range(0, 200_000, 200))
    assert list(bits(sum(1 << i for i in indices))) == indices
