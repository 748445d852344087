"""Registers plumetrace's environments with Gymnasium (``gymnasium.make`` ids).

Imported by plumetrace.env when gymnasium is installed; also usable as a ``gymnasium.envs``
entry point (``plumetrace = "plumetrace.registration:register_envs"``), which Gymnasium runs at
``import gymnasium``. It imports nothing of plumetrace's own, so that a plugin never stops
``import gymnasium``: the environment class is loaded only when ``gymnasium.make`` needs it.
"""

ENV_ID = "plumetrace/Lochmatter2008-v0"
"""The paper's scenario (PlumeEnv() with its defaults)."""


def register_envs():
    """Registers ENV_ID with gymnasium, once (later calls do nothing)."""
    import gymnasium

    if ENV_ID not in gymnasium.registry:
        gymnasium.register(id=ENV_ID, entry_point="plumetrace.env:PlumeEnv")
