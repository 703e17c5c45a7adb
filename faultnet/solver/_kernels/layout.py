"""Named layouts of the small packed arrays the entry kernels share with Python.

The Python layer and the kernels read and write these arrays only through the names here.

``ctrl`` (float64[CTRL_SIZE]): the run's numerical options, and whether the keys need a rebuild.
``scal`` (float64[SCAL_SIZE]): the frame offset and the plate position relative to it.
``cnt`` (int64[CNT_SIZE]): counters of the current call.
``out`` (float64[OUT_SIZE]): the last event's catalog row, as the kernel left it.
``solo`` (float64[n_classes, SOLO_SIZE]): the cached solo slip of each parameter class.
``cat_f`` (float64[n_events, CAT_F_SIZE]), ``cat_i`` (int64[n_events, CAT_I_SIZE]): the event
catalog, one row per event.
``trace_buf`` (float64[rows, TRACE_X + 2 m]): one row per step of an event for the ``m`` traced
blocks: the event, the time, their positions ``[TRACE_X, TRACE_X + m)`` and velocities
``[TRACE_X + m, TRACE_X + 2 m)``.

The OFC automaton's entry (:mod:`.ofc`) shares ``scal`` and has its own ``OFC_CTRL_*``,
``OFC_CNT_*`` and catalog columns ``OFC_CAT_*``.
"""

__all__ = [
    "CAT_BLOCKS",
    "CAT_DURATION",
    "CAT_FAULTS",
    "CAT_F_SIZE",
    "CAT_HYPOCENTER",
    "CAT_I_SIZE",
    "CAT_S",
    "CAT_STEPS",
    "CAT_T",
    "CNT_BLOCK_STEPS",
    "CNT_EVENTS",
    "CNT_INTERPOLATED_CROSSINGS",
    "CNT_PARTIAL_BLOCK_STEPS",
    "CNT_RELOCATIONS",
    "CNT_RETAKEN_STEPS",
    "CNT_REVEALED_JOINS",
    "CNT_SIZE",
    "CNT_SLIP_ROWS",
    "CNT_SOLO_EVENTS",
    "CNT_STAMPS",
    "CNT_STEPS",
    "CNT_TRACE_FULL",
    "CNT_TRACE_ROWS",
    "CTRL_DT",
    "CTRL_MAX_DURATION",
    "CTRL_MAX_VELOCITY",
    "CTRL_REBUILD",
    "CTRL_SIZE",
    "CTRL_SOLO_CACHE",
    "CTRL_STOP",
    "OFC_CAT_BLOCKS",
    "OFC_CAT_FAULTS",
    "OFC_CAT_F_SIZE",
    "OFC_CAT_GENERATIONS",
    "OFC_CAT_HYPOCENTER",
    "OFC_CAT_I_SIZE",
    "OFC_CAT_S",
    "OFC_CAT_T",
    "OFC_CAT_TOPPLINGS",
    "OFC_CHUNK_SHIFT",
    "OFC_CNT_EVENTS",
    "OFC_CNT_GENERATIONS",
    "OFC_CNT_SIZE",
    "OFC_CNT_STAMP",
    "OFC_CNT_TOPPLINGS",
    "OFC_CTRL_MAX_TOPPLINGS",
    "OFC_CTRL_REBUILD",
    "OFC_CTRL_SIZE",
    "OUT_BLOCKS",
    "OUT_DURATION",
    "OUT_FAULTS",
    "OUT_HYPOCENTER",
    "OUT_SIZE",
    "OUT_SLIP",
    "OUT_STEPS",
    "OUT_T",
    "SCAL_OFFSET",
    "SCAL_SIZE",
    "SCAL_W",
    "SOLO_DURATION",
    "SOLO_SIZE",
    "SOLO_SLIP",
    "SOLO_SPEED",
    "SOLO_STEPS",
    "TRACE_EVENT",
    "TRACE_TIME",
    "TRACE_X",
]

CTRL_DT = 0  #: integration step inside events
CTRL_MAX_DURATION = 1  #: longest allowed event (time units)
CTRL_MAX_VELOCITY = 2  #: fastest allowed block velocity
CTRL_SOLO_CACHE = 3  #: 1.0: reuse cached solo slips; 0.0: integrate every event
#: 1.0: recompute every key and the tree from ``z`` before the next event (set where the
#: arrays are built, cleared by the kernel)
CTRL_REBUILD = 4
#: 1.0: stop at the end of the step; the event under way is undone (set from another thread)
CTRL_STOP = 5
CTRL_SIZE = 6

SCAL_OFFSET = 0  #: integer-valued frame offset
SCAL_W = 1  #: plate position minus the offset
SCAL_SIZE = 2

CNT_EVENTS = 0  #: events completed in this call
CNT_SLIP_ROWS = 1  #: rows used in the per-block slip buffer
CNT_TRACE_ROWS = 2  #: rows used in the trajectory buffer
CNT_STEPS = 3  #: integration steps (full and partial)
CNT_BLOCK_STEPS = 4  #: block-steps (slipping blocks x steps)
CNT_TRACE_FULL = 5  #: 1 once the trajectory buffer filled up
CNT_PARTIAL_BLOCK_STEPS = 6  #: block-steps of partial steps to crossings
CNT_RELOCATIONS = 7  #: an earlier crossing found inside a partial step
CNT_SOLO_EVENTS = 8  #: events taken from a cached solo slip
CNT_STAMPS = 9  #: tag counter of the steps' scans (never reset)
CNT_INTERPOLATED_CROSSINGS = 10  #: stops and joins placed on a step's dense output
CNT_RETAKEN_STEPS = 11  #: interpolated steps taken again at half length
CNT_REVEALED_JOINS = 12  #: joins revealed by interpolated crossings (each take of a step)
CNT_SIZE = 13

OUT_T = 0  #: plate time of the last event's start
OUT_DURATION = 1  #: its duration
OUT_SLIP = 2  #: its total slip S
OUT_BLOCKS = 3  #: the blocks that slipped
OUT_HYPOCENTER = 4  #: block index of the last event's hypocentre
OUT_STEPS = 5  #: integration steps it took
OUT_FAULTS = 6  #: the faults among the blocks that slipped
OUT_SIZE = 7

SOLO_SLIP = 0  #: a parameter class's solo slip (NaN until computed)
SOLO_DURATION = 1  #: its duration
SOLO_STEPS = 2  #: its integration steps
#: a bound on its fastest velocity (viscous models: a dashpot pulls a neighbour by eta v)
SOLO_SPEED = 3
SOLO_SIZE = 4

CAT_T = 0  #: ``cat_f`` column: plate time of the event's start
CAT_DURATION = 1  #: ``cat_f`` column: the event's duration
CAT_S = 2  #: ``cat_f`` column: its total slip S
CAT_F_SIZE = 3
CAT_BLOCKS = 0  #: ``cat_i`` column: the blocks that slipped
CAT_HYPOCENTER = 1  #: ``cat_i`` column: block index of the hypocentre
CAT_STEPS = 2  #: ``cat_i`` column: integration steps the event took
CAT_FAULTS = 3  #: ``cat_i`` column: the faults among the blocks that slipped
CAT_I_SIZE = 4

TRACE_EVENT = 0  #: ``trace_buf`` column: the event's number
TRACE_TIME = 1  #: ``trace_buf`` column: time since the event's start
TRACE_X = 2  #: ``trace_buf`` columns from here: the traced blocks' positions, then velocities

# The OFC automaton (:mod:`.ofc`): ``ctrl`` (float64[OFC_CTRL_SIZE]), ``cnt`` (int64[OFC_CNT_SIZE]),
# ``cat_f`` (float64[n_events, OFC_CAT_F_SIZE]) and ``cat_i`` (int64[n_events, OFC_CAT_I_SIZE]).
#: the OFC tree's leaves are chunks of ``2**OFC_CHUNK_SHIFT`` consecutive blocks (see :mod:`.ofc`)
OFC_CHUNK_SHIFT = 5
OFC_CTRL_MAX_TOPPLINGS = 0  #: the most topplings one avalanche may take (then the entry stops)
#: 1.0: build the tree from the keys before the next avalanche (set where the arrays are built,
#: cleared by the kernel)
OFC_CTRL_REBUILD = 1
OFC_CTRL_SIZE = 2

OFC_CNT_EVENTS = 0  #: avalanches completed in this call
OFC_CNT_TOPPLINGS = 1  #: topplings in this call
OFC_CNT_GENERATIONS = 2  #: generations in this call
OFC_CNT_STAMP = 3  #: tag counter of the avalanches' and generations' marks (never reset)
OFC_CNT_SIZE = 4

OFC_CAT_T = 0  #: ``cat_f`` column: the drive at the avalanche's start
OFC_CAT_S = 1  #: ``cat_f`` column: its total slip S
OFC_CAT_F_SIZE = 2
OFC_CAT_TOPPLINGS = 0  #: ``cat_i`` column: its topplings
OFC_CAT_BLOCKS = 1  #: ``cat_i`` column: the distinct blocks that toppled
OFC_CAT_HYPOCENTER = 2  #: ``cat_i`` column: block index of the block that reached 1 first
OFC_CAT_FAULTS = 3  #: ``cat_i`` column: the faults among the blocks that toppled
OFC_CAT_GENERATIONS = 4  #: ``cat_i`` column: its generations (synchronous steps)
OFC_CAT_I_SIZE = 5
