"""Block indices to node labels: a simulator makes the label array once, and every chunk's
frames index it as they would the labels themselves."""

import numpy as np
import pytest

from faultnet.solver.result import label_array, node_labels

IDX = np.array([2, 0, 2, 1])


@pytest.mark.parametrize(
    "labels, want",
    [
        ([10, 20, 30], [30, 10, 30, 20]),
        (range(5, 11, 2), [9, 5, 9, 7]),
        (["a", "b", "c"], ["c", "a", "c", "b"]),
        ([(0, 1), (1, 0), (2, 2)], [(2, 2), (0, 1), (2, 2), (1, 0)]),
        ([np.int32(4), 5, np.int64(6)], [6, 4, 6, 5]),
        ([True, 1, 2], [2, True, 2, 1]),  # a bool is a label of its own, not an int
    ],
)
def test_label_array_indexes_as_the_labels_do(labels, want):
    once = label_array(labels)
    for got in (node_labels(labels, IDX), node_labels(once, IDX)):
        assert list(got) == want
        assert all(
            type(g) is type(w) or isinstance(g, np.integer) for g, w in zip(got, want, strict=True)
        )
    ints = all(isinstance(w, int) and not isinstance(w, bool) for w in want)
    assert (node_labels(once, IDX).dtype == np.int64) == ints


def test_a_model_without_faults_has_no_fault_labels():
    assert label_array(None) is None
