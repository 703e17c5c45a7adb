"""Named layouts of the small packed arrays the entry kernels share with Python.

The Python layer and the kernels read and write these arrays only through the names here.

``ctrl`` (float64[CTRL_SIZE]): the run's numerical options.
``scal`` (float64[SCAL_SIZE]): the frame offset and the plate position relative to it.
``cnt`` (int64[CNT_SIZE]): counters of the current call.
``out`` (float64[OUT_SIZE]): the last event's catalog row, as the kernel left it.
``solo`` (float64[n_classes, SOLO_SIZE]): the cached solo slip of each parameter class.
"""

__all__ = [
    "CNT_BLOCK_STEPS",
    "CNT_EVENTS",
    "CNT_INTERPOLATED_CROSSINGS",
    "CNT_LANDED_JOINS",
    "CNT_LOCAL_FALLBACKS",
    "CNT_LOCAL_STEPS",
    "CNT_PARTIAL_BLOCK_STEPS",
    "CNT_REGION_BLOCK_STEPS",
    "CNT_REGION_IDS",
    "CNT_RELOCATIONS",
    "CNT_SIZE",
    "CNT_SLIP_ROWS",
    "CNT_SOLO_EVENTS",
    "CNT_STEPS",
    "CNT_TRACE_FULL",
    "CNT_TRACE_ROWS",
    "CTRL_DT",
    "CTRL_LOCAL_FROM",
    "CTRL_MAX_DURATION",
    "CTRL_MAX_VELOCITY",
    "CTRL_SIZE",
    "CTRL_SOLO_CACHE",
    "OUT_BLOCKS",
    "OUT_DURATION",
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
    "SOLO_STEPS",
]

CTRL_DT = 0  #: integration step inside events
CTRL_MAX_DURATION = 1  #: longest allowed event (time units)
CTRL_MAX_VELOCITY = 2  #: fastest allowed block velocity
CTRL_SOLO_CACHE = 3  #: 1.0: reuse cached solo slips; 0.0: integrate every event
CTRL_LOCAL_FROM = 4  #: slipping blocks from which crossings are handled in local regions
CTRL_SIZE = 5

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
CNT_LOCAL_STEPS = 9  #: steps whose crossings were handled in local regions
CNT_LOCAL_FALLBACKS = 10  #: local steps handed back to the whole-event treatment
CNT_REGION_IDS = 11  #: id counter of local regions (never reset)
CNT_REGION_BLOCK_STEPS = 12  #: block-steps inside local regions
CNT_LANDED_JOINS = 13  #: joins landed on a step's interpolant
CNT_INTERPOLATED_CROSSINGS = 14  #: stops and joins placed on a step's dense output
CNT_SIZE = 16

OUT_T = 0  #: plate time of the last event's start
OUT_DURATION = 1  #: its duration
OUT_SLIP = 2  #: its total slip S
OUT_BLOCKS = 3  #: the blocks that slipped
OUT_HYPOCENTER = 4  #: block index of the last event's hypocentre
OUT_STEPS = 5  #: integration steps it took
OUT_SIZE = 6

SOLO_SLIP = 0  #: a parameter class's solo slip (NaN until computed)
SOLO_DURATION = 1  #: its duration
SOLO_STEPS = 2  #: its integration steps
SOLO_SIZE = 3
