"""The models: the Carlson-Langer block-spring model and its sparse graph.

Also the state of a running model (positions, plate, stuck slips), the
stiffness spectrum that sets the step, and the hash that identifies a model.
"""
