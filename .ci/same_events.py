"""Check that catalogs written under different dependency versions hold the same events.

Usage: python .ci/same_events.py REFERENCE OTHER [OTHER ...]; exits 1 on the first difference.
"""

import sys

import pandas as pd

import faultnet


def main(reference, *others):
    ref = faultnet.read_catalog(reference)
    for path in others:
        cat = faultnet.read_catalog(path)
        pd.testing.assert_frame_equal(cat.events, ref.events, check_exact=True)
        print(
            f"{path}: {len(cat.events):,} events bit-identical to {reference} (numba "
            f"{cat.metadata['provenance']['numba']} vs {ref.metadata['provenance']['numba']})"
        )


if __name__ == "__main__":
    main(*sys.argv[1:])
