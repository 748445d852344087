"""The learned policy: its inputs (features), its network, its file, and the controller that runs
it in any run, sweep or benchmark (docs/vector.md, "A learned baseline").

A policy decides every ``decision_interval`` simulation steps from one observation frame of
:class:`plumetrace.vector.VectorPlumeEnv` with ``observe=OBSERVE`` (binary odor at the last
sensing, the share of the decision's sensings with odor, one wind sample in the robot frame, the
odometry pose and odometer; float32), and holds the command in between. It keeps a memory of its
own past frames (:class:`Memory`): the decisions since the last odor hit, and where that hit was.
From the frame and the memory it computes ``FEATURES`` and passes them through one hidden layer
of tanh units to one tanh output ``a`` in [-1, 1], the vector environment's action.

The same functions serve training (a batch of environments, each with its own weights) and the
controller (a batch of one): elementwise NumPy operations in a fixed order, so an environment's
action does not depend on the batch it is computed in.
"""

import json
import math
from pathlib import Path

import numpy as np

from ..controllers import Command, Controller, wrap_angle

__all__ = ["ACTIONS", "FEATURES", "OBSERVE", "Learned", "Memory", "Policy", "features",
           "forward", "load_policy", "policy_path"]

OBSERVE = ("odor", "odor_fraction", "wind", "odometry")
"""What the policy observes: VectorPlumeEnv(observe=OBSERVE), a frame of 8 float32 values."""

ACTIONS = ("turn", "heading")
"""How the output becomes a command (VectorPlumeEnv's ``action``): "turn" goes along the current
odometry heading plus pi a, "heading" along the odometry heading pi a."""

FEATURES = ("odor", "odor_fraction", "upwind_cos", "upwind_sin", "upwind_angle", "recent_odor",
            "cast_cos", "cast_sin", "to_hit_x", "to_hit_y", "heading_cos", "heading_sin")
"""The network's inputs, in order (docs/vector.md, "A learned baseline"): the binary odor and the
odor fraction; the upwind direction in the robot frame (cos, sin, and its angle over pi) from
the wind sample; exp(-k / memory) after k decisions without odor (0 before the first hit); a
phase 2 pi sqrt(k / cast_period) (cos, sin) of the decisions k since the last hit (or the
release), whose half-periods grow by cast_period / 2 decisions each, for casts that widen;
the way back to the last hit's position in the robot frame, d / (1 + |d|) (0 before the first
hit); the odometry heading (cos, sin)."""

_FILE = Path(__file__).resolve().parent / "learned.json"
_FORMAT = "plumetrace-learned-policy"


def policy_path():
    """The shipped policy's file (learned.json beside this module)."""
    return _FILE


class Policy:
    """A network and what its inputs mean: `decision_interval` (simulation steps per decision),
    `action` (one of ACTIONS), `hidden` (tanh units), `memory` (decisions for the odor memory to
    fall by a factor e), `cast_period` (decisions of the cast phase's first period), and
    `theta`, the flat weights (``Policy.size(hidden)`` of them: W1 (hidden x inputs), b1, w2,
    b2). `info`: a dict of how it was trained, kept with it in its file."""

    def __init__(self, theta=None, *, decision_interval=8, action="turn", hidden=8,
                 memory=20.0, cast_period=32, info=None):
        from ..api import _finite_number, _whole

        self.decision_interval = _whole("decision_interval", decision_interval, 1, 2**31 - 1)
        if not isinstance(action, str) or action not in ACTIONS:
            raise ValueError(f"action must be one of {ACTIONS}, got {action!r}")
        self.action = action
        self.hidden = _whole("hidden", hidden, 1, 4096)
        self.memory = _finite_number("memory", memory, 0.0, strict=True)
        self.cast_period = _whole("cast_period", cast_period, 1, 2**20)
        if theta is None:
            theta = np.zeros(self.size(self.hidden))
        theta = np.array(theta, dtype=np.float64)
        if theta.shape != (self.size(self.hidden),):
            raise ValueError(f"theta: shape {theta.shape}; a policy of {self.hidden} hidden units "
                             f"has {self.size(self.hidden)} weights")
        if not np.all(np.isfinite(theta)):
            raise ValueError("theta: every weight must be a finite number")
        self.theta = theta
        self.info = dict(info or {})
        self._memory_table = np.zeros((0, 3))

    def memory_values(self, since):
        """exp(-k / memory), cos and sin of 2 pi sqrt(k / cast_period) for the decisions `since`
        (an int array): rows of a table made once with Python's math functions, so that they are
        the same numbers in every batch and on every machine."""
        need = int(since.max(initial=0)) + 1
        table = self._memory_table
        if need > len(table):
            size = max(need, 2 * len(table), 1024)
            rows = [(math.exp(-k / self.memory), math.cos(2 * math.pi * math.sqrt(
                k / self.cast_period)), math.sin(2 * math.pi * math.sqrt(k / self.cast_period)))
                for k in range(len(table), size)]
            table = self._memory_table = np.vstack([table, np.array(rows)])
        return table[since]

    @staticmethod
    def size(hidden):
        """The number of weights of a network with `hidden` units."""
        return hidden * len(FEATURES) + 2 * hidden + 1

    def with_theta(self, theta, info=None):
        """The same policy with other weights."""
        return Policy(theta, decision_interval=self.decision_interval, action=self.action,
                      hidden=self.hidden, memory=self.memory, cast_period=self.cast_period,
                      info=self.info if info is None else info)

    def initial(self, rng, scale=1.0):
        """Random weights for a start (N(0, scale^2 / inputs) on W1, N(0, scale^2 / hidden) on
        w2, zero biases), drawn from the NumPy generator `rng`."""
        n, h = len(FEATURES), self.hidden
        theta = np.zeros(self.size(h))
        theta[:h * n] = rng.standard_normal(h * n) * scale / math.sqrt(n)
        theta[h * n + h:h * n + 2 * h] = rng.standard_normal(h) * scale / math.sqrt(h)
        return theta

    def act(self, memory, frames, thetas=None):
        """The actions (array of len(frames)) for `frames` (n x 8 float32, one frame per
        environment, as VectorPlumeEnv gives them with observe=OBSERVE), updating `memory` (a
        Memory of n); `thetas`: n x size weights, one row per environment (default: this
        policy's for all)."""
        x = features(self, memory, frames)
        if thetas is None:
            thetas = np.broadcast_to(self.theta, (len(x), self.theta.size))
        return forward(thetas, x, self.hidden)

    def command(self, a, heading):
        """The command of action `a` for a robot whose odometry heading is `heading` (rad), as
        the vector environment makes it."""
        a = min(max(float(a), -1.0), 1.0)
        if self.action == "turn":
            return Command.go(wrap_angle(heading + math.pi * a))
        return Command.go(math.pi * a)

    def to_dict(self):
        """The policy as the JSON its file holds."""
        return {"format": _FORMAT, "version": 1, "features": list(FEATURES),
                "observe": list(OBSERVE), "decision_interval": self.decision_interval,
                "action": self.action, "hidden": self.hidden, "memory": self.memory,
                "cast_period": self.cast_period, "theta": [float(v) for v in self.theta],
                "info": self.info}

    def save(self, path):
        """Writes the policy to `path` (JSON; floats written so they read back exactly)."""
        from .._files import write_whole

        text = json.dumps(self.to_dict(), indent=1) + "\n"
        write_whole(path, text)

    @classmethod
    def from_dict(cls, d, where="policy"):
        """A Policy from the dict of to_dict(); ValueError naming `where` if it is not one."""
        if not isinstance(d, dict) or d.get("format") != _FORMAT:
            raise ValueError(f"{where}: not a plumetrace learned policy (format '{_FORMAT}')")
        if d.get("features") != list(FEATURES) or d.get("observe") != list(OBSERVE):
            raise ValueError(f"{where}: its features {d.get('features')} are not this version's "
                             f"{list(FEATURES)}")
        try:
            return cls(d["theta"], decision_interval=d["decision_interval"], action=d["action"],
                       hidden=d["hidden"], memory=d["memory"], cast_period=d["cast_period"],
                       info=d.get("info"))
        except KeyError as e:
            raise ValueError(f"{where}: no {e.args[0]!r}") from None
        except (TypeError, ValueError) as e:
            raise ValueError(f"{where}: {e}") from None

    def __repr__(self):
        return (f"Policy(hidden={self.hidden}, action={self.action!r}, decision_interval="
                f"{self.decision_interval}, memory={self.memory}, cast_period={self.cast_period})")


def load_policy(path=None):
    """The policy in `path` (default: the shipped one, policy_path()); BadPath naming the file if
    it cannot be read or is not a policy."""
    from .._files import BadPath, read_input

    path = _FILE if path is None else Path(path)
    try:
        d = json.loads(read_input(path, "policy file").decode("utf-8"))
        return Policy.from_dict(d, f"policy file '{path}'")
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        raise BadPath(f"policy file '{path}': not JSON ({e})") from None
    except ValueError as e:
        if isinstance(e, BadPath):
            raise
        raise BadPath(str(e)) from None


class Memory:
    """What a policy remembers of its past frames, for `n` environments: the decisions since the
    last odor hit (or since the release, before one), whether there was one, and its position
    (odometry frame, m)."""

    def __init__(self, n):
        self.since = np.zeros(n, dtype=np.int64)
        self.hit = np.zeros(n, dtype=bool)
        self.at = np.zeros((n, 2))
        self.fresh = np.ones(n, dtype=bool)  # the next frame is an episode's first

    def restart(self, mask):
        """Marks the environments of `mask` (bools) as starting a new episode at the next frame."""
        self.fresh |= np.asarray(mask, dtype=bool)


def features(policy, memory, frames):
    """The network's inputs (n x len(FEATURES), float64) for `frames` (n x 8, float32), after
    updating `memory` with them (see FEATURES)."""
    f = np.asarray(frames, dtype=np.float32).astype(np.float64)
    if f.ndim != 2 or f.shape[1] != 8:
        raise ValueError(f"frames: shape {f.shape}; a frame holds 8 values ({OBSERVE})")
    odor, fraction, wx, wy, x, y, heading = (f[:, j] for j in range(7))
    m = memory
    # decisions since the last hit: 0 at a hit and at an episode's first frame
    hit = fraction > 0.0
    m.since = np.where(hit | m.fresh, 0, m.since + 1)
    m.hit = np.where(m.fresh, hit, m.hit | hit)
    m.fresh[:] = False
    m.at[hit] = f[hit][:, 4:6]
    out = np.empty((len(f), len(FEATURES)))
    out[:, 0] = odor
    out[:, 1] = fraction
    speed = np.sqrt(wx * wx + wy * wy)
    calm = speed == 0.0
    safe = np.where(calm, 1.0, speed)
    out[:, 2] = np.where(calm, 1.0, -wx / safe)
    out[:, 3] = np.where(calm, 0.0, -wy / safe)
    out[:, 4] = np.arctan2(out[:, 3], out[:, 2]) / np.pi
    values = policy.memory_values(m.since)
    out[:, 5] = np.where(m.hit, values[:, 0], 0.0)
    out[:, 6:8] = values[:, 1:3]
    c, s = np.cos(heading), np.sin(heading)
    dx, dy = m.at[:, 0] - x, m.at[:, 1] - y
    scale = np.where(m.hit, 1.0 / (1.0 + np.sqrt(dx * dx + dy * dy)), 0.0)
    out[:, 8] = (c * dx + s * dy) * scale
    out[:, 9] = (c * dy - s * dx) * scale
    out[:, 10] = c
    out[:, 11] = s
    return out


def forward(thetas, x, hidden):
    """The network's outputs in [-1, 1] for inputs `x` (n x len(FEATURES)), environment i with
    the weights thetas[i] (n x Policy.size(hidden)): tanh(w2 . tanh(W1 x + b1) + b2). Sums are
    made term by term in a fixed order, so a row's value does not depend on the others."""
    n_in, h = len(FEATURES), hidden
    w1 = thetas[:, :h * n_in].reshape(len(x), h, n_in)
    b1 = thetas[:, h * n_in:h * n_in + h]
    w2 = thetas[:, h * n_in + h:h * n_in + 2 * h]
    b2 = thetas[:, h * n_in + 2 * h]
    z = b1.copy()
    for k in range(n_in):
        z += w1[:, :, k] * x[:, k:k + 1]
    z = np.tanh(z)
    o = b2.copy()
    for j in range(h):
        o += w2[:, j] * z[:, j]
    return np.tanh(o)


_SHIPPED = []  # the shipped policy, read once per process


class Learned(Controller):
    """The shipped learned policy as a controller (registered as "learned" by
    examples/learned.py): it decides every decision_interval steps from the first sensing on,
    holds the command between, takes one wind sample per decision and computes the frame the
    vector environment gives, so that it plays exactly what the policy played in training.
    ``Learned(policy=p)`` runs another Policy."""

    state = "learned"

    def __init__(self, params=None, rng=None, policy=None):
        super().__init__(params, rng)
        if policy is None:
            if not _SHIPPED:
                _SHIPPED.append(load_policy())
            policy = _SHIPPED[0]
        self.policy = policy
        self.memory = Memory(1)
        self.steps = 0
        self.odor_count = 0
        self.held = None

    def step(self, obs, wind):
        d = self.policy.decision_interval
        self.odor_count += 1 if obs.odor else 0
        if self.steps % d == 0:
            # the frame: the first decision sees its one sensing, a later one the d held steps
            sensed = 1 if self.steps == 0 else d
            wx, wy = wind.measure_wind_body()
            p = obs.odometry
            frame = np.array([[1.0 if obs.odor else 0.0, self.odor_count / sensed, wx, wy,
                               p.x, p.y, p.heading, obs.odometer]], dtype=np.float32)
            a = self.policy.act(self.memory, frame)[0]
            self.held = self.policy.command(a, p.heading)
            self.odor_count = 0
        self.steps += 1
        return self.held
