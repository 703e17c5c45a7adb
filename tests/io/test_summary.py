"""Catalog statistics (faultnet.io.summary): streamed magnitudes, b fits, text lines."""

import math

import numpy as np
import pytest

import faultnet
from faultnet.exceptions import CatalogError
from faultnet.io import parquet as fio
from faultnet.io.summary import (
    LSQ_TOP_QUANTILE,
    catalog_stats,
    fit_b_values,
    format_stats,
    read_magnitudes,
)
from faultnet.stats import fit_b_lsq, fit_b_mle


@pytest.fixture(scope="module")
def chunked(tmp_path_factory):
    """A 2500-event catalog merged from 8 chunk files (8 row groups) and its result."""
    folder = tmp_path_factory.mktemp("summary")
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(40), alpha=2.0)
    res = faultnet.simulate(model, 2500, rng=9, progress=False)
    bounds = np.linspace(0, 2500, 9).astype(int)
    chunks = []
    for i, (a, b) in enumerate(zip(bounds[:-1], bounds[1:], strict=True)):
        events = res.events.iloc[a:b].reset_index(drop=True)
        chunks.append(fio.write_part(events, folder / f"c{i}.parquet", {}))
    out = fio.merge_parts(chunks, folder / "cat.parquet", dict(res.metadata, transient=100))
    return out, res


def test_read_magnitudes_thins_across_row_groups(chunked):
    out, res = chunked
    M = res.events["M"].to_numpy()
    got, step = read_magnitudes(out, skip=100, max_n=1000)
    assert step == 3
    np.testing.assert_array_equal(got, M[100::3])
    got, step = read_magnitudes(out, skip=1000)  # the skip ends inside a row group
    assert step == 1
    np.testing.assert_array_equal(got, M[1000:])
    assert read_magnitudes(out, skip=5000)[0].size == 0


def test_catalog_stats_match_the_in_memory_fits(chunked):
    out, res = chunked
    events = res.events
    st = catalog_stats(out)  # the transient recorded in the metadata
    assert st["events"] == 2500 and st["transient"] == 100 and st["events_fit"] == 2400
    assert st["t_first"] == events["t"].iloc[0] and st["t_last"] == events["t"].iloc[-1]
    assert st["M_min"] == events["M"].min() and st["M_max"] == events["M"].max()
    assert st["largest_n_blocks"] == events["n_blocks"].max()
    M = events["M"].to_numpy()[100:]
    mle = fit_b_mle(M)
    top = float(np.quantile(M[M >= mle.m_min], LSQ_TOP_QUANTILE))  # the default LSQ window
    lsq = fit_b_lsq(M, mle.m_min, top)
    assert st["b_mle"] == mle.b and st["n_fit"] == mle.n and st["b_lsq"] == lsq.b
    assert catalog_stats(out, transient=0)["n_fit"] != st["n_fit"]


def test_fit_b_values_reports_impossible_fits():
    out = fit_b_values([1.0, np.nan])
    assert math.isnan(out["b_mle"]) and math.isnan(out["b_lsq"]) and out["n_fit"] == 0
    assert "MLE fit failed" in out["fit_note"]


def test_text_summary(chunked, tmp_path):
    out, res = chunked
    cat = fio.read_catalog(out)
    text = cat.summary()
    st = catalog_stats(out)
    assert format_stats(cat.metadata, st) in text
    assert f"b (MLE)     {st['b_mle']:.3f} ± {st['b_mle_err']:.3f}" in text
    assert "events      2,500 (first 0)" in text
    assert "graph       ring(40): 40 blocks, 40 springs" in text
    with pytest.raises(CatalogError, match="needs a catalog read from a file"):
        fio.Catalog(events=res.events).summary()
    with pytest.raises(CatalogError, match="does not exist"):
        catalog_stats(tmp_path / "missing.parquet")


def test_a_small_error_is_never_printed_as_zero():
    from faultnet.io.summary import format_stats

    st = {
        "events": 10**7, "transient": 0, "events_fit": 10**7, "t_first": 0.0, "t_last": 1.0,
        "M_min": -7.0, "M_max": 4.0, "largest_n_blocks": 9, "n_fit": 10**7, "m_min": -6.9,
        "m_max": 3.0, "b_mle": 0.46213, "b_mle_err": 0.00031, "b_lsq": 0.5, "b_lsq_err": 0.004,
    }  # fmt: skip
    text = format_stats({}, st)
    assert "0.4621 ± 0.0003" in text and "0.500 ± 0.004" in text and "± 0.000 " not in text


@pytest.fixture(scope="module")
def merging(tmp_path_factory):
    """Catalog files of a ring of 1000 at nu = 1e-3 (events merge) and 1e-4 (they do not)."""
    folder = tmp_path_factory.mktemp("plate")
    out = {}
    for nu, n in [(1e-3, 400), (1e-4, 2000)]:
        model = faultnet.CarlsonLanger(faultnet.graphs.ring(1000), nu=nu)
        res = faultnet.simulate(model, n, rng=1, progress=False)
        out[nu] = fio.write_catalog(res, folder / f"nu{nu:g}.parquet"), res
    return out


def _share(res):
    """The plate's advance during events over its whole advance, from the events."""
    ev, nu = res.events, res.metadata["nu"]
    during = nu * ev["duration"].sum()
    return during / (ev["t"].iloc[-1] - ev["t"].iloc[0] + during / len(ev))


def test_merging_events_get_a_note_with_a_moving_plate(merging):
    """At nu = 1e-3 the plate makes 96% of its advance inside events on a ring of 1000, and
    the summary says that events merge; at 1e-4, 41%, and it says nothing."""
    path, res = merging[1e-3]
    share = _share(res)
    assert share > 0.9
    text = format_stats(res.metadata, catalog_stats(path))
    mean = res.events["n_blocks"].mean()
    assert f"the plate made {share:.1%} of its advance during events" in text
    assert f"events merge ({mean:.1f} of 1000 blocks on average)" in text
    path, res = merging[1e-4]
    assert _share(res) < 0.5
    assert "note        with nu" not in format_stats(res.metadata, catalog_stats(path))


def test_the_plate_note_needs_a_moving_plate_and_two_events():
    from faultnet.io.summary import plate_note

    st = {"events": 5, "t_first": 0.0, "t_last": 1.0, "sum_duration": 4000.0, "sum_n_blocks": 50}
    assert plate_note({"nu": 1e-3, "n_blocks": 10}, st).startswith("with nu = 0.001")
    assert plate_note({"nu": 0.0, "n_blocks": 10}, st) is None
    assert plate_note({"n_blocks": 10}, {**st, "sum_duration": 0.0}) is None
    assert plate_note({"nu": 1e-3, "n_blocks": 10}, {**st, "events": 1}) is None
    assert plate_note({"nu": 1e-3}, {k: v for k, v in st.items() if k != "sum_duration"}) is None
