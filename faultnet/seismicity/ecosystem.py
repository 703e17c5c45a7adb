r"""Bridges to the seismologists' tools: SeismoStats catalogs, QuakeML, powerlaw fits.

Install with ``pip install "faultnet[seismo]"`` (SeismoStats and powerlaw);
both are imported inside the functions, so ``import faultnet`` stays fast.

Magnitude conventions
---------------------
faultnet's magnitude is ``M = ln S`` (``S`` the total slip of an event) and
its exponent ``b`` is that of :math:`P(M) \propto e^{-bM}` (Sakaguchi & Morita
2013; :mod:`faultnet.stats.magnitudes`).  :func:`to_seismostats` writes one of three
magnitudes, chosen with ``magnitude=``:

``"moment"`` (default)
    A moment-magnitude-like ``m = (2/3) log10 S + offset`` (slip as a proxy of
    the seismic moment, ``Mw = (2/3) log10 M0 + const``).  Then
    ``ln S = (3/2) ln(10) (m - offset)`` and
    :math:`P(m) \propto e^{-b (3/2) \ln(10)\, m} = 10^{-1.5\, b\, m}`:
    the Gutenberg-Richter ``b_GR = 1.5 b`` (:attr:`faultnet.BFit.b_gr`;
    the paper's ``b = 2/3`` is ``b_GR = 1``).
``"log10"``
    ``m = log10 S + offset``: :math:`P(m) \propto 10^{-b m}`, ``b_GR = b``.
``"ln"``
    ``m = ln S + offset = M + offset`` as is: SeismoStats' ``beta = b`` and its
    ``b_value = b / ln 10``.

SeismoStats' ``b_value`` is the base-10 exponent of its magnitudes and its
``beta = b_value ln 10``; powerlaw's ``Fit`` fits :math:`P(S) \propto S^{-\alpha}`
on the slips, ``alpha = 1 + b`` (:attr:`faultnet.BFit.powerlaw_alpha`).
:data:`B_VALUE_FACTOR` holds ``b_value / b`` for each magnitude choice.

Time and place
--------------
Plate time ``t`` (units of ``1/v0``) becomes ``origin + t * time_unit``
(default: 1 unit = one Julian year from 2000-01-01).  With a graph, the
hypocentre's ``pos`` (arc length on a ring) is placed on a local flat map:
``spacing_km`` kilometres per lattice spacing east and north of
``(lon0, lat0)``, at a fixed ``depth`` in metres (QuakeML's unit).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from faultnet.exceptions import InvalidParameterError
from faultnet.stats.magnitudes import fit_b_mle

__all__ = ["B_VALUE_FACTOR", "compare_b", "magnitudes", "to_quakeml", "to_seismostats"]

#: SeismoStats ``b_value`` / faultnet ``b`` for each magnitude choice of :func:`to_seismostats`
B_VALUE_FACTOR = {"moment": 1.5, "log10": 1.0, "ln": 1.0 / math.log(10.0)}
_MAG_TYPE = {"moment": "Mw", "log10": "Mlog10S", "ln": "MlnS"}
_KM_PER_DEGREE = 111.195  # mean Earth radius 6371 km


def magnitudes(M, magnitude="moment", offset=0.0):
    """Convert ``M = ln S`` to the magnitude scale ``magnitude`` (module docstring).

    >>> round(float(magnitudes(np.log(1000.0), "moment")), 12)
    2.0
    >>> round(float(magnitudes(np.log(1000.0), "log10")), 12), float(magnitudes(1.5, "ln", 1.0))
    (3.0, 2.5)
    """
    if magnitude not in B_VALUE_FACTOR:
        raise InvalidParameterError(
            f"magnitude must be one of {sorted(B_VALUE_FACTOR)}; got {magnitude!r}"
        )
    M = np.asarray(M, dtype=np.float64)
    if magnitude == "moment":
        return (2.0 / 3.0) * M / math.log(10.0) + offset
    if magnitude == "log10":
        return M / math.log(10.0) + offset
    return M + offset


def _events_frame(events):
    if hasattr(events, "events") and hasattr(events, "model"):
        return events.events, events.model
    if not isinstance(events, pd.DataFrame) or not {"t", "M"} <= set(events.columns):
        raise InvalidParameterError(
            "events must be a SimulationResult or an events DataFrame with columns t and M"
        )
    return events, None


def to_seismostats(
    events,
    graph=None,
    magnitude="moment",
    offset=0.0,
    origin="2000-01-01",
    time_unit="365.25D",
    spacing_km=1.0,
    lon0=0.0,
    lat0=0.0,
    depth=10_000.0,
    name=None,
):
    """A :class:`seismostats.Catalog` of a faultnet catalog.

    Parameters
    ----------
    events : pandas.DataFrame or SimulationResult
        Events with ``t``, ``M``, and ``hypocenter`` for positions.  Events with
        a non-finite ``M`` (zero slip) are left out.
    graph : networkx.Graph, SparseGraph, CarlsonLanger, optional
        Graph of the run (taken from a SimulationResult by default); without
        one every event sits at ``(lon0, lat0)``.
    magnitude : {"moment", "log10", "ln"}
        Magnitude scale (module docstring); ``b_value = B_VALUE_FACTOR[magnitude] * b``.
    offset : float
        Added to the magnitudes.
    origin, time_unit : str or pandas.Timestamp / Timedelta
        Calendar time of ``t = 0`` and the length of one unit of plate time.
    spacing_km, lon0, lat0, depth
        Flat map of the hypocentres: km per unit of ``pos``, the map's origin
        and the depth in metres.
    name : str, optional
        Catalog name (default from the run's graph).

    Returns
    -------
    seismostats.Catalog
        Columns ``time``, ``magnitude``, ``magnitude_type`` (``Mw``,
        ``Mlog10S`` or ``MlnS``), ``longitude``, ``latitude``, ``depth``,
        ``eventID``/``originID``/``magnitudeID`` (``smi:faultnet/...``) and
        faultnet's ``event``, ``t``, ``S``, ``n_blocks``, ``hypocenter``;
        ``delta_m = 0`` (continuous magnitudes).
    """
    from seismostats import Catalog

    frame, model = _events_frame(events)
    graph = model if graph is None else graph
    frame = frame[np.isfinite(frame["M"].to_numpy(dtype=np.float64))]
    n = len(frame)
    mags = magnitudes(frame["M"].to_numpy(dtype=np.float64), magnitude, offset)
    time = pd.Timestamp(origin) + frame["t"].to_numpy(dtype=np.float64) * pd.Timedelta(time_unit)
    east = north = np.zeros(n)
    if graph is not None and "hypocenter" in frame.columns:
        from faultnet.seismicity.geometry import geometry

        geo = geometry(graph)
        if geo.coords is None:
            raise InvalidParameterError("the graph has no node positions ('pos') to map")
        xy = geo.coords[geo.indices(frame["hypocenter"].tolist())]
        east, north = xy[:, 0] * spacing_km, xy[:, 1] * spacing_km
    lat = lat0 + north / _KM_PER_DEGREE
    lon = lon0 + east / (_KM_PER_DEGREE * math.cos(math.radians(lat0)))
    ids = frame["event"].to_numpy() if "event" in frame.columns else np.arange(n)
    data = {
        "eventID": [f"smi:faultnet/event/{i}" for i in ids],
        "originID": [f"smi:faultnet/origin/{i}" for i in ids],
        "magnitudeID": [f"smi:faultnet/magnitude/{i}" for i in ids],
        "time": time,
        "magnitude": mags,
        "magnitude_type": _MAG_TYPE[magnitude],
        "longitude": lon,
        "latitude": lat,
        "depth": np.full(n, float(depth)),
    }
    for col in ("event", "t", "S", "n_blocks", "hypocenter"):
        if col in frame.columns:
            data[col] = frame[col].to_numpy()
    if name is None and model is not None:
        name = f"faultnet {model.graph.graph.get('name', '')}".strip()
    return Catalog(pd.DataFrame(data), name=name, delta_m=0.0)


def to_quakeml(events, path=None, agency_id="faultnet", author="faultnet", **kwargs):
    """QuakeML 1.2 text of a faultnet catalog (through :func:`to_seismostats`).

    Parameters
    ----------
    events : pandas.DataFrame or SimulationResult
    path : str or pathlib.Path, optional
        Also write the text there.
    agency_id, author : str
        QuakeML ``creationInfo``.
    **kwargs
        Passed to :func:`to_seismostats` (magnitude choice, time, map).

    Returns
    -------
    str
    """
    xml = to_seismostats(events, **kwargs).to_quakeml(agencyID=agency_id, author=author)
    if path is not None:
        from pathlib import Path

        Path(path).write_text(xml, encoding="utf-8")
    return xml


def compare_b(events, m_min, magnitude="moment"):
    """The b-value of one catalog by faultnet, SeismoStats and powerlaw, in both conventions.

    faultnet's :func:`~faultnet.stats.fit_b_mle` on ``M >= m_min``;
    SeismoStats' ``Catalog.estimate_b`` (classic Aki/Tinti-Mulargia MLE,
    ``delta_m = 0``, Shi & Bolt error) on the :func:`to_seismostats` catalog
    with ``mc`` = ``m_min`` converted; powerlaw's ``Fit`` on the slips
    ``S >= exp(m_min)``.  Each native estimate is converted to the paper's
    ``b`` (``b_value / B_VALUE_FACTOR[magnitude]``, ``alpha - 1``).

    Returns
    -------
    pandas.DataFrame
        Index ``faultnet``, ``seismostats``, ``powerlaw``; columns
        ``quantity`` (the native parameter), ``value``, ``error``, ``b``,
        ``b_err`` (paper convention) and ``n``.
    """
    import warnings

    import powerlaw

    frame, _ = _events_frame(events)
    M = frame["M"].to_numpy(dtype=np.float64)
    M = M[np.isfinite(M)]
    fit = fit_b_mle(M, m_min=m_min)
    factor = B_VALUE_FACTOR[magnitude]
    cat = to_seismostats(frame[np.isfinite(frame["M"])], graph=None, magnitude=magnitude)
    mc = float(magnitudes(float(m_min), magnitude))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # "no magnitudes in the lowest bin": continuous data
        est = cat.estimate_b(mc=mc, delta_m=0.0)
        pl = powerlaw.Fit(np.exp(M), xmin=math.exp(float(m_min)), discrete=False, verbose=False)
    alpha, alpha_err = float(pl.power_law.alpha), float(pl.power_law.standard_err)
    rows = {
        "faultnet": ("b (P(M) ~ exp(-b M), M = ln S)", fit.b, fit.b_err, fit.b, fit.b_err, fit.n),
        "seismostats": (
            f"b_value ({_MAG_TYPE[magnitude]})",
            float(est.b_value),
            float(est.std),
            float(est.b_value) / factor,
            float(est.std) / factor,
            int(est.n),
        ),
        "powerlaw": (
            "alpha (P(S) ~ S^-alpha)",
            alpha,
            alpha_err,
            alpha - 1.0,
            alpha_err,
            int(pl.n_tail),
        ),
    }
    return pd.DataFrame.from_dict(
        rows, orient="index", columns=["quantity", "value", "error", "b", "b_err", "n"]
    )
