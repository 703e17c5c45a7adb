"""What a cold compile of the default scheme compiles, in order (generated: do not edit).

(module, kernel, argument types, spine), callees before callers; regenerate with
``python -m faultnet._compile_helper --record`` after changing kernels (a test fails
while this list is stale).
"""

__all__ = ["ENTRY", "ORDER"]

ENTRY = 'run_events_dopri5'
ORDER = [
    ('tree', 'block_key', ('i8', 'f8[::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'f8[::1]'), False),
    ('tree', '_winner', ('i8', 'i8', 'f8[::1]'), False),
    ('tree', 'build_keys_and_tree', ('f8[::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]', 'i8[::1]'), False),
    ('dopri', 'boundary_positions', ('i8', 'f8', 'f8[:,::1]', 'i8[:,::1]', 'f8[::1]'), False),
    ('integrate', 'poly_root', ('f8', 'f8', 'f8', 'f8', 'f8', 'f8', 'f8'), False),
    ('integrate', 'hermite_root', ('f8', 'f8', 'f8', 'f8', 'f8', 'f8'), False),
    ('integrate', 'hermite_fall', ('f8', 'f8', 'f8'), False),
    ('integrate', 'hermite_dip', ('f8', 'f8', 'f8', 'f8'), False),
    ('crossing', 'stick_theta', ('lit1', 'f8', 'i8', 'i8', 'f8[:,::1]'), False),
    ('crossing', 'join_theta', ('lit1', 'f8', 'i8', 'i8', 'f8', 'f8', 'f8[:,::1]', 'i8[:,::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]'), False),
    ('dopri', 'dopri_step', ('f8', 'i8', 'i8', 'i8[:,::1]', 'f8[:,::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]', 'i8', 'f8', 'f8[::1]'), True),
    ('stepping', 'commit', ('i8', 'i8', 'f8[:,::1]', 'i8[:,::1]'), False),
    ('local', '_new_id', ('i8[::1]',), False),
    ('local', '_listed', ('i8', 'i8[:,::1]', 'f8[::1]'), False),
    ('local', '_collect', ('f8', 'i8', 'i8', 'f8[:,::1]', 'i8[:,::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]'), False),
    ('local', '_save', ('i8', 'i8', 'f8[:,::1]', 'i8[:,::1]', 'f8[::1]'), False),
    ('local', '_grow', ('i8', 'i8', 'i8', 'i8', 'i8', 'f8[:,::1]', 'i8[:,::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]'), False),
    ('local', '_component', ('i8', 'i8', 'i8', 'i8', 'i8[:,::1]', 'i8[::1]', 'i8[::1]'), False),
    ('dopri', 'cache_boundary', ('i8', 'i8', 'f8[:,::1]', 'i8[:,::1]', 'f8[::1]'), False),
    ('local', '_border', ('i8', 'i8', 'i8', 'f8[:,::1]', 'i8[:,::1]', 'f8[::1]'), False),
    ('local', '_enclose', ('i8', 'i8', 'i8', 'i8', 'i8', 'f8[:,::1]', 'i8[:,::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]'), False),
    ('local', '_first_crossing', ('i8', 'i8', 'i8[:,::1]', 'f8[::1]'), False),
    ('stepping', 'restore_positions', ('i8', 'i8', 'f8[:,::1]', 'i8[:,::1]'), False),
    ('landing', 'septic_root', ('f8', 'f8', 'f8', 'f8', 'f8', 'f8', 'f8', 'f8', 'f8'), False),
    ('landing', '_join_theta', ('f8', 'i8', 'f8', 'i8', 'f8[:,::1]', 'i8[:,::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'f8[::1]'), False),
    ('dopri', 'boundary_at', ('f8', 'f8[:,::1]', 'i8[:,::1]', 'f8[::1]'), False),
    ('landing', '_place', ('f8', 'i8', 'f8', 'i8', 'i8', 'f8[:,::1]', 'i8[:,::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]'), False),
    ('landing', 'land', ('f8', 'i8', 'f8', 'i8', 'i8', 'i8', 'i8[:,::1]', 'f8[:,::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]'), False),
    ('stepping', '_residual', ('i8', 'i8', 'f8[:,::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'f8[::1]'), False),
    ('stepping', '_taylor_shift', ('f8', 'i8', 'i8', 'f8[:,::1]', 'i8[:,::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]'), False),
    ('stepping', '_polish', ('f8', 'f8', 'i8', 'i8', 'lit1', 'i8', 'i8', 'i8[:,::1]', 'f8[:,::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]'), False),
    ('local', '_escapes', ('i8', 'i8', 'i8[:,::1]', 'i8[::1]', 'i8[::1]'), False),
    ('local', '_claim_neighbours', ('i8', 'i8', 'i8', 'i8', 'i8', 'f8[:,::1]', 'i8[:,::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]'), False),
    ('stepping', 'touch', ('i8', 'f8', 'f8[::1]', 'f8[:,::1]', 'i8[:,::1]', 'i8'), False),
    ('stepping', 'activate', ('i8', 'i8', 'i8', 'f8', 'f8[::1]', 'f8[:,::1]', 'i8[:,::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]'), False),
    ('stepping', 'join_scan', ('i8', 'i8', 'i8', 'f8', 'f8[::1]', 'f8[:,::1]', 'i8[:,::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]'), False),
    ('stepping', 'deactivate', ('i8', 'i8', 'f8[:,::1]', 'i8[:,::1]'), False),
    ('stepping', 'stick_scan', ('i8', 'i8', 'f8[:,::1]', 'i8[:,::1]'), False),
    ('local', '_quiet', ('i8', 'i8', 'f8[:,::1]', 'i8[:,::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]'), False),
    ('local', '_finish', ('i8', 'i8', 'f8[:,::1]', 'i8[:,::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]'), False),
    ('local', '_restore', ('i8', 'f8[:,::1]', 'i8[:,::1]', 'f8[::1]'), False),
    ('events', '_record_trace', ('i8', 'f8', 'f8', 'f8[::1]', 'f8[:,::1]', 'i8[::1]', 'f8[:,::1]', 'i8[::1]'), False),
    ('events', '_integrate', ('lit1', 'i8', 'i8', 'i8', 'f8', 'f8[::1]', 'f8[::1]', 'f8[::1]', 'f8[:,::1]', 'i8[:,::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]', 'f8[::1]', 'i8[::1]', 'f8[:,::1]', 'i8[::1]'), True),
    ('events', '_solo_free', ('i8', 'f8', 'f8', 'f8[::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]'), False),
    ('tree', 'tree_update', ('i8', 'f8[::1]', 'i8[::1]'), False),
    ('events', '_solo_apply', ('i8', 'f8', 'i8', 'f8[::1]', 'f8[::1]', 'i8[::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'f8[::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'i8[::1]'), False),
    ('events', '_finish_event', ('i8', 'i8', 'f8[::1]', 'f8[::1]', 'i8[::1]', 'f8[:,::1]', 'i8[:,::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'f8[::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'i8[::1]'), False),
    ('events', '_recentre', ('f8[::1]', 'f8[::1]', 'f8[::1]', 'i8[::1]', 'i8[::1]', 'i8[::1]', 'f8[::1]', 'f8[::1]'), False),
]
