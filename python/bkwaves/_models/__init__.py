"""The run models: one entry per model, looked up by the config, the runner, the run-cost
estimate, the outputs and the command line instead of a branch in each of them.

A model is one module of this package defining ``MODEL``, an instance of a
:class:`Model` subclass. It says

- its TOML: the keys of ``[domain]`` and how they become :class:`~bkwaves.config.RunConfig`
  fields (:meth:`Model.parse_domain`, :meth:`Model.domain_doc`), its boundaries, which
  ``[disorder]`` properties it has, whether it takes triggers, an initial velocity, the
  chain's integration keys of ``[run]``, a ``[speed]`` law, friction laws other than
  Coulomb, and how its ``[noise]`` rate scales with the units;
- its checks of quantities derived from several keys (:meth:`Model.check`);
- its grid (:meth:`Model.x`, :meth:`Model.nodes`, :meth:`Model.span`);
- its run (:meth:`Model.run`: build the engine from a validated config, or restore it
  from a checkpoint, advance it, hand the writer its snapshots and tables);
- its run-cost estimate (:meth:`Model.work`, :attr:`Model.bytes_per_node`).

Adding a model is one module and one line in :data:`NAMES`.
"""

from __future__ import annotations

import importlib

from .._core import ParameterError

__all__ = ["NAMES", "Model", "get"]

#: The models a config's ``model`` key can name (module names of this package).
NAMES = ("chain", "free_boundary", "lattice", "free_boundary_2d")

_LOADED: dict = {}


def get(name: str) -> Model:
    """The entry of model ``name`` (one of :data:`NAMES`)."""
    m = _LOADED.get(name)
    if m is None:
        if name not in NAMES:
            raise ParameterError(
                f"model: unknown model {name!r}; allowed: {', '.join(map(repr, NAMES))}"
            )
        m = importlib.import_module(f".{name}", __name__).MODEL
        _LOADED[name] = m
    return m


class Model:
    """What every model says about itself (the defaults are the chain's where a model
    has nothing to say: no triggers, no initial velocity, no chain [run] keys)."""

    #: the config's ``model`` value
    name: str = ""
    #: boundary conditions of one axis
    boundaries: tuple[str, ...] = ()
    #: the [domain] keys (all), and those required
    domain_keys: tuple[str, ...] = ()
    domain_required: tuple[str, ...] = ()
    #: the config key a too large domain is named by
    size_key: str = ""
    #: [disorder] properties, and whether a smooth random field
    #: {mean, amplitude, correlation_length} is one of their forms
    disorder_keys: tuple[str, ...] = ()
    correlated_disorder: bool = False
    #: [disorder] properties that may be 0 (the lattice's bonds: a zero bond cuts it);
    #: the others must be > 0
    disorder_zero_ok: tuple[str, ...] = ()
    #: [disorder] threshold is the static threshold field of a free boundary model
    #: (``bkwaves.config.threshold_field``)
    threshold_field: bool = False
    #: blocks with friction (the chain's engine): the friction law in the outputs
    discrete: bool = False
    #: [[triggers]], [initial] velocity, the chain's [run] integration keys
    triggers: bool = False
    initial_velocity: bool = False
    chain_run_keys: bool = False
    #: a [speed] law; friction laws other than coulomb
    speed_law: bool = False
    coulomb_only: bool = False
    #: the noise keys of ``bkwaves.noise.check_noise`` (its ``model``): "chain", noise
    #: per block (spontaneous slips), or "free_boundary", per unit length (or area) of
    #: the continuum (pair nucleation)
    noise_kind: str = "chain"
    #: what the noise rate is per, its SI unit, and the power of the length scale in it
    noise_per: str = "block"
    noise_si: str = "1/s"
    noise_length_power: int = 0
    #: with v = 0 nothing loads the field: a run bounded by events only is refused
    events_need_loading: bool = False
    #: engine memory per node (bytes, measured; bkwaves.limits.LIMITS names it)
    bytes_per_node_key: str = ""
    #: bytes per node of one snapshot record
    snapshot_bytes_per_node: int = 8
    #: [output] arrivals: the arrival (first slip) times of every rupture as a table
    arrivals: bool = False
    #: the [initial] kinds it takes
    initial_kinds: tuple[str, ...] = ("uniform", "ramp", "random", "bumps", "file")
    #: what `bkwaves run --help` says about it
    summary: str = ""

    # --- config ------------------------------------------------------------------------
    def parse_domain(self, d: dict, cfg_value) -> dict:
        """The RunConfig fields of the [domain] table ``d`` (``cfg_value(d, key)``
        checks a key against ``bkwaves._validate.CONFIG["domain"]``)."""
        raise NotImplementedError

    def domain_doc(self, cfg) -> dict:
        """The [domain] table of ``cfg`` (RunConfig.to_dict)."""
        raise NotImplementedError

    def scale_noise(self, noise: dict, ts: float, ls: float, vs: float) -> dict:
        """A [noise] table given in SI turned dimensionless (time, length, speed
        scales); default: a rate per block and unit time, a kick speed."""
        noise["rate"] *= ts
        if "kick" in noise:
            noise["kick"] /= vs
        return noise

    def scale_domain(self, domain: dict, ls: float) -> dict:
        """The [domain] fields given in metres turned dimensionless (length scale
        ``ls``); default: nothing in metres."""
        return domain

    def check_keys(self, cfg) -> None:
        """Combinations of keys the model refuses (before any field is drawn)."""

    def check(self, cfg) -> None:
        """Checks of quantities derived from several keys (after the keys)."""

    def trigger_block(self, tr: dict, where: str, domain: dict):
        """The block of the trigger table ``tr`` (``where``: its key path), checked
        against the [domain] fields ``domain``."""
        from .. import _validate as V
        from ..config import _err, _value

        block = _value(tr, "block", where, V.CONFIG["triggers"]["block"])
        n = self.domain_nodes(domain)
        if block >= n:
            _err(f"{where}.block", f"invalid block = {block}: allowed 0 <= block < {n}")
        return block

    def parse_trigger(self, tr: dict, where: str, domain: dict):
        """A Trigger of the [[triggers]] table ``tr`` when the model has its own form of
        them (else None: time, a place of ``trigger_places``, kind, velocity)."""
        return None

    def scale_trigger_place(self, block, ls: float):
        """A trigger's place given in metres turned dimensionless (length scale ``ls``);
        default: blocks, not lengths."""
        return block

    #: the keys of a [[triggers]] table that place it (exactly one is given)
    trigger_places: tuple[str, ...] = ("block",)

    def trigger_doc(self, block) -> dict:
        """The place of a trigger as its table's keys (RunConfig.to_dict)."""
        return {"block": block}

    def domain_nodes(self, domain: dict) -> int:
        """Blocks of the [domain] fields ``domain``."""
        return domain.get("blocks", 0)

    def initial_state(self, cfg):
        """The initial u at the nodes (dimensionless)."""
        from ..config import initial_line

        return initial_line(cfg)

    def check_initial(self, cfg, u, x, key: str) -> None:
        """Checks of the initial state ``u`` at the nodes ``x`` (``key``: the [initial]
        keys that made it)."""

    def physical_span(self, cfg) -> float:
        """The extent of the positions (dimensionless) an SI output converts."""
        return self.span(cfg)

    def physical_lengths(self, cfg) -> tuple:
        """(key, dimensionless value) of lengths given in metres, to be finite and > 0."""
        return ()

    def property_arrays(self, cfg) -> dict:
        """{property: scalar, array or None} of the [disorder] table (checked > 0)."""
        return {}

    # --- grid ----------------------------------------------------------------------------
    def x(self, cfg):
        """Node positions along x (dimensionless)."""
        raise NotImplementedError

    def nodes(self, cfg) -> int:
        """Blocks or grid nodes."""
        raise NotImplementedError

    def size_text(self, cfg) -> str:
        """The size key's value in words (``size_key``)."""
        return str(self.nodes(cfg))

    def span(self, cfg) -> float:
        """The domain's extent along x (dimensionless length)."""
        raise NotImplementedError

    # --- run -----------------------------------------------------------------------------
    def run(self, cfg, out, progress, overwrite, flush_every, chunk, ctl):
        """Run ``cfg`` (bkwaves.runner.run's body): a RunSummary."""
        raise NotImplementedError

    # --- cost ----------------------------------------------------------------------------
    def work(self, cfg):
        """(work, count, wall): the ``bkwaves._cost`` work of the run, its count (block
        steps, crossings) and ``wall(work, nodes, snapshots, output)`` in seconds."""
        raise NotImplementedError

    def check_noise_events(self, cfg, what: str) -> None:
        """A run bounded only by events, with noise: warn where events may never end."""

    def noise_size(self, cfg) -> float:
        """What the noise rate is per: blocks (chain) or domain size (continuum)."""
        return self.nodes(cfg)
