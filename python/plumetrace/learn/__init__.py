"""A learned plume-tracking baseline (docs/vector.md, "A learned baseline"): a small policy
network trained with an evolution strategy on the vector environment, and the controller that
runs it.

    from plumetrace.learn import Learned, load_policy, es
    pt.register_controller("learned", Learned)              # the shipped policy
    policy, curve = es.train(["laminar"], generations=50)   # python3 -m plumetrace.learn.es
    pt.run(controller=lambda scenario, rng: Learned(policy=policy))

Submodules: ``policy`` (the features, the network, the policy file and the controller) and
``es`` (the trainer, its command line and its learning-curve plot).
"""

from .policy import ACTIONS, FEATURES, OBSERVE, Learned, Memory, Policy, load_policy, policy_path

__all__ = ["ACTIONS", "FEATURES", "OBSERVE", "Learned", "Memory", "Policy", "es", "load_policy",
           "policy_path"]


def __getattr__(name):
    # why: the trainer is imported on first use, so that `python3 -m plumetrace.learn.es` runs it
    # as a script without importing it twice
    if name == "es":
        import importlib

        return importlib.import_module(".es", __name__)
    raise AttributeError(f"module 'plumetrace.learn' has no attribute {name!r}")
