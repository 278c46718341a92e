"""The paper's control laws (§III, eqs 4-10 and Algorithm 1) and the improved mode, as pure functions.

One module per law; :mod:`vehicle_agents.control.step` is the single entry point that both the lockstep engine
and the per-process agent call with what one drone knows: its own odometry, its camera's perception result and
the neighbours it heard over the radio.
"""
