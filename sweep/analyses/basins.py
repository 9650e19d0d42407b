"""Analysis ``basins``: basins of attraction and dynamic integrity (the paper's Fig. 19).

A lattice of initial conditions ``(q_j, dq_j/dt)`` at ``t = 0`` (mode ``j`` of the ROM,
the other state components zero; on a model whose state is not modal, the full model, the
state the map lifts them to, :func:`model.protocol.modal_lift`, and its attractors are
reported by their modal section) is classified by the attractor of the stroboscopic map
each trajectory ends on (:mod:`model.basins`).  The lattice is cut into tiles of
interleaved ``ic_x`` rows (tile ``t`` has rows ``t, t + tiles, ...``), one subtask each; the tile layout depends on the options only (``tiles``),
never on the rank count.  Every tile finds its attractors itself (Newton on recurrences);
:meth:`Basins.assemble` merges them across tiles by matching their Poincare points,
numbers them by decreasing amplitude (attractor 0 is the largest, the resonant one in
Fig. 19), relabels the lattice and computes the integrity measures of
:mod:`model.integrity` (``basin_fraction`` is the global integrity measure).

With ``method = "fast"``, a ROM evaluated by quadrature (more than one mode) is rebuilt
with the fewest radial points that leave its accelerations unchanged to 1e-10 on the states of the trajectories
from the window's corners and edge midpoints (:func:`model.rom.lean_radial_points`,
:func:`model.lattice.window_states`); the result records them (``radial_points``).  The
accelerations are checked again on the attractors found: a tile where they differ by more
than :data:`LEAN_RTOL` gets status not converged.  For
modes (1..3, 0) on the Fig. 19a window: 32 points instead of 160, with accelerations within
2.2e-11 of the full rule's on all 200,400 stroboscopic states of 400 trajectories of 2500
periods (the window's sample: 3.8e-11), a third of the cost per RK4 step.

Options: :attr:`Basins.OPTIONS` (``docs/options.md``).

Grid points outside the job's ``[grid] cases`` (Fig. 19 pairs delta with Omega) are not
computed: label -2 and NaN measures.

A spot check of a fast run: ``method = "brute"`` with ``sample = N`` classifies only ``N``
initial conditions of the lattice, drawn at random (:data:`SAMPLE_SEED`; the same ones
whatever the tiles and ranks), the others are not computed (label -2); the fractions
(``basin_fraction``, ``unclassified_fraction``) are then over the sample and the
``integrity_factor``, which needs the whole lattice, is NaN.

The labels' sensitivity: ``perturbation = eps`` scales every initial state by ``1 + eps``
before it is classified; a run with it against one without, on the same sample, measures the
share of initial conditions whose fate a change of that size decides (docs/model.md,
"Basins of attraction").

Labels: ``0..n-1`` attractor index, ``-1`` unclassified (no periodic attractor of period
``<= max_period`` reached within ``max_periods``: a non-periodic attractor or a very long
transient), ``-2`` not computed (outside ``cases``, or not in the ``sample``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial

import numpy as np

from model import attractors as ma
from model import basin_cells as mc
from model import basins as mb
from model import lattice as ml
from model.forced import ForcedMap
from model.integrity import global_integrity_measure, integrity_factor
from model.params import Loading, Membrane
from model.protocol import modal_lift, modal_section

from sweep.models.rom import rom_for

from . import options as opt
from .base import DEFAULT_CONTEXT, GRID_KEYS, STATUS_NOT_CONVERGED, STATUS_OK, Analysis, JobError, Variable, check_keys

_SECTION = "basins"
NOT_COMPUTED = -2
#: Largest ``num`` of ``ic_x`` and ``ic_y``.
MAX_LATTICE = 4096
#: Largest number of initial conditions in one tile (one task).
MAX_TILE_POINTS = 65_536
#: Tolerance of the lean quadrature (model.rom.lean_radial_points), on the window's states
#: and again on the attractors found: far below the RK4 error of a period.
LEAN_RTOL = 1e-10
#: Seed of the random ``sample`` of the lattice.
SAMPLE_SEED = 19


@dataclass(frozen=True)
class BasinsOptions:
    """Validated options of the ``basins`` analysis (see the module docstring)."""

    modes: tuple[tuple[int, int], ...]
    prestretch: str
    lattice_mode: int
    ic_x: tuple[float, float, int]
    ic_y: tuple[float, float, int]
    method: str
    tiles: int
    steps: int | None
    settings: mb.Settings
    max_attractors: int
    #: initial conditions classified, drawn at random from the lattice (None: all of them)
    sample: int | None = None
    #: every initial state scaled by ``1 + perturbation`` (the labels' sensitivity)
    perturbation: float = 0.0
    #: the job's material law (``[membrane] law``): the warmups compile its kernels
    material: str = "neo-hookean"
    #: whether the job's model is the ROM, whose kernels the warmups compile (another
    #: model's compile on their first call)
    rom_kernels: bool = True

    @property
    def rows(self) -> int:
        """``ic_x`` rows per tile (at most)."""
        return math.ceil(self.ic_x[2] / self.tiles)

    def tile_rows(self, tile: int) -> np.ndarray:
        """The ``ic_x`` rows of ``tile``: every ``tiles``-th row from row ``tile``.

        Interleaved rows give every tile a share of the whole window, so tiles cost about
        the same (the transients from the window's edge are the longest) and each tile's
        cell map learns the whole plane.
        """
        return np.arange(tile, self.ic_x[2], self.tiles)

    def sampled(self, rows: np.ndarray) -> np.ndarray:
        """Which initial conditions of lattice rows ``rows`` are classified (row-major, as
        :func:`model.lattice.lattice_states`): all of them, or those of the ``sample``."""
        nx, ny = self.ic_x[2], self.ic_y[2]
        if self.sample is None:
            return np.ones(rows.size * ny, bool)
        chosen = np.zeros(nx * ny, bool)
        chosen[np.random.default_rng(SAMPLE_SEED).choice(nx * ny, size=self.sample, replace=False)] = True
        return chosen.reshape(nx, ny)[rows].ravel()

    @property
    def n_state(self) -> int:
        """State dimension ``2K``."""
        return 2 * len(self.modes)

    def lattice(self) -> ml.Lattice:
        """The lattice of initial conditions."""
        K = len(self.modes)
        return ml.Lattice(np.linspace(*self.ic_x), np.linspace(*self.ic_y),
                          self.lattice_mode - 1, K + self.lattice_mode - 1)


class Basins(Analysis):
    """Basins of attraction on a lattice of initial conditions (Fig. 19)."""

    name = "basins"
    model_needs = ("forced_map",)
    #: The option table ``[basins]``: key -> description (docs/options.md).
    OPTIONS = {
        "modes": opt.MODES_HELP,
        "prestretch": "analytic (Eq. 21) | numeric (Eq. 15, default) | fit (Eq. 18)",
        "lattice_mode": "1-based index in modes of the lattice coordinates (default 1)",
        "ic_x": "{start, stop, num}: initial displacement q_j (m; default -0.3 to 0.3, 100; num <= 4096)",
        "ic_y": "{start, stop, num}: initial velocity dq_j/dt (m/s; default -10 to 10, 100; num <= 4096)",
        "method": "fast (cells and proximity, default; more modes: cells of the whole state space) | brute "
                  "(proximity only: the reference)",
        "sample": "N: with method = \"brute\", classify only N initial conditions drawn at random from the "
                  "lattice (label -2 elsewhere; fractions over the sample, integrity_factor NaN), a spot check "
                  "of a fast run on the same lattice (default: the whole lattice)",
        "perturbation": "eps: every initial state scaled by 1 + eps before it is classified (default 0); the "
                        "share of a run's labels that another run with eps changes is the uncertain fraction "
                        "of the lattice at that eps (final-state sensitivity, Grebogi et al. 1983)",
        "tiles": "tiles of interleaved ic_x rows, one task each (default 8, at most ic_x.num, raised to "
                 "keep 65,536 initial conditions or fewer per tile)",
        "steps": opt.steps_help(mb.DEFAULT_STEPS),
        "max_periods": "periods before a trajectory is unclassified, label -1 (default 20000)",
        "radius": "capture radius around attractor points, fraction of the lattice window (default 0.01)",
        "consecutive": "consecutive clean-cell hits to adopt a cell's label (default 8 for one mode, 16 for "
                       "more and on the full model)",
        "guard": "one mode: half-width of the block of equal labels around a clean cell (default 2)",
        "cell_resolution": "about this many cells per lattice axis in the cell map (one mode of the ROM: of the "
                           "lattice plane, default 200; more modes, and the full model: in every state "
                           "coordinate, default 100; at most 4096; 0: the lattice's)",
        "max_period": "largest period of the attractors searched, in forcing periods (default 4)",
        "max_attractors": "attractors stored per grid point (default 6)",
    }
    required_grid = ("delta", "delta_o", "Omega", "P0", "c")

    def parse_options(self, table, grid, membrane, context=DEFAULT_CONTEXT) -> BasinsOptions:
        check_keys(table, _SECTION, tuple(self.OPTIONS))
        modes = opt.modes(table, _SECTION)
        opt.model_modes(_SECTION, context.model, modes)
        opt.damping_modes(context.damping, _SECTION, modes, None)
        lm = opt.number(table, _SECTION, "lattice_mode", 1, low=1, high=len(modes),
                        integer=True)
        ic_x = opt.linspace(table, _SECTION, "ic_x", {"start": -0.3, "stop": 0.3, "num": 100},
                            max_num=MAX_LATTICE)
        ic_y = opt.linspace(table, _SECTION, "ic_y", {"start": -10.0, "stop": 10.0, "num": 100},
                            max_num=MAX_LATTICE)
        for key, (a, b, num) in (("ic_x", ic_x), ("ic_y", ic_y)):
            if num < 2 or not b > a:
                raise JobError(f"{_SECTION}.{key}", table.get(key),
                               "needs stop > start and num >= 2")
        method = opt.choice(table, _SECTION, "method", ("fast", "brute"), "fast")
        sample = None
        if "sample" in table:
            sample = opt.number(table, _SECTION, "sample", low=1, high=ic_x[2] * ic_y[2], integer=True)
            if method != "brute":
                raise JobError(f"{_SECTION}.sample", sample, 'needs method = "brute" (the fast method '
                               "classifies whole lattice rows)")
        # a model whose state is not its modal coordinates has more than two state
        # coordinates even for one mode: the settings of the state-space cell map
        d = mb.default_settings(max(len(modes), 2) if context.model.model().axisymmetric_states else len(modes))
        settings = mb.Settings(
            max_periods=opt.number(table, _SECTION, "max_periods", d.max_periods, low=1, integer=True),
            radius=opt.number(table, _SECTION, "radius", d.radius, low=0.0, low_open=True, high=0.5),
            consecutive=opt.number(table, _SECTION, "consecutive", d.consecutive, low=1, integer=True),
            guard=opt.number(table, _SECTION, "guard", d.guard, low=0, integer=True),
            cell_resolution=opt.number(table, _SECTION, "cell_resolution", d.cell_resolution, low=0,
                                       high=MAX_LATTICE, integer=True),
            max_period=opt.number(table, _SECTION, "max_period", d.max_period, low=1, high=64,
                                  integer=True))
        return BasinsOptions(
            modes=modes, prestretch=opt.prestretch(table, _SECTION, context), lattice_mode=lm,
            ic_x=ic_x, ic_y=ic_y, method=method,
            tiles=min(max(opt.number(table, _SECTION, "tiles", 8, low=1, integer=True),
                          math.ceil(ic_x[2] * ic_y[2] / MAX_TILE_POINTS)), ic_x[2]),
            steps=opt.steps(table, _SECTION, mb.DEFAULT_STEPS, low=8, high=None),
            settings=settings,
            max_attractors=opt.number(table, _SECTION, "max_attractors", 6, low=1, high=1000,
                                      integer=True),
            sample=sample, perturbation=opt.number(table, _SECTION, "perturbation", 0.0, low=0.0, high=1e-2),
            material=membrane.law, rom_kernels=context.model.kind == "rom")

    def n_subtasks(self, options: BasinsOptions) -> int:
        return options.tiles

    def variables(self, options: BasinsOptions) -> list[Variable]:
        R, ny, A = options.rows, options.ic_y[2], options.max_attractors
        P, S = options.settings.max_period, options.n_state
        return [
            Variable("tile_label", ("tile_row", "ic_y"), (R, ny), "i4", "1",
                     "attractor index within the tile (-1 unclassified)", NOT_COMPUTED),
            Variable("tile_periods", ("tile_row", "ic_y"), (R, ny), "i4", "1",
                     "forcing periods integrated per initial condition", 0),
            Variable("tile_attractor_point", ("tile_attractor", "phase", "state"), (A, P, S),
                     "f8", "1", "Poincare points of the tile's attractors (SI)", np.nan),
            Variable("tile_attractor_period", ("tile_attractor",), (A,), "i4", "1",
                     "period of the tile's attractors in forcing periods (0: none)", 0),
            Variable("tile_attractor_amplitude", ("tile_attractor",), (A,), "f8", "m",
                     "max |w(0.5 Re, 0, t)| on the tile's attractors", np.nan),
            Variable("tile_attractor_multiplier", ("tile_attractor",), (A,), "f8", "1",
                     "largest Floquet multiplier modulus of the tile's attractors", np.nan),
            Variable("tile_rk4_steps", (), (), "i4", "1", "RK4 steps per forcing period", 0),
            Variable("tile_radial_points", (), (), "i4", "1", "radial quadrature points of the ROM", 0),
            Variable("tile_state_cells", (), (), "i4", "1",
                     "cells in the tile's state-space cell map (a state of more than two coordinates, fast "
                     "method; else 0)", 0),
        ]

    def coords(self, options: BasinsOptions):
        return {"ic_y": (("ic_y",), np.linspace(*options.ic_y),
                         {"units": "m s-1", "long_name": "initial modal velocity"})}

    def compute(self, point, options: BasinsOptions, subtask: int):
        R, ny, A = options.rows, options.ic_y[2], options.max_attractors
        P, S = options.settings.max_period, options.n_state
        out = {"tile_label": np.full((R, ny), NOT_COMPUTED, np.int32),
               "tile_periods": np.zeros((R, ny), np.int32),
               "tile_attractor_point": np.full((A, P, S), np.nan),
               "tile_attractor_period": np.zeros(A, np.int32),
               "tile_attractor_amplitude": np.full(A, np.nan),
               "tile_attractor_multiplier": np.full(A, np.nan),
               "status": STATUS_OK}
        full = fmap = point.model.forced_map(point, options, default_steps=mb.DEFAULT_STEPS)
        steps = getattr(fmap, "steps", 0)
        lattice = options.lattice()
        if options.method == "fast" and hasattr(fmap, "lean"):  # (brute force, the reference, keeps the full rule)
            fmap = fmap.lean(partial(ml.window_states, lattice, fmap), LEAN_RTOL)
        out["tile_rk4_steps"] = steps
        out["tile_radial_points"] = getattr(fmap, "radial_points", 0)
        rows = options.tile_rows(subtask)
        chosen = options.sampled(rows)
        states = modal_lift(fmap, ml.lattice_states(lattice, rows, S)[chosen]) * (1.0 + options.perturbation)
        cell_report: dict = {}
        labels, atts, periods = mb.classify_lattice(states, lattice, fmap, options.settings,
                                                    use_cells=options.method == "fast", report=cell_report,
                                                    scale=ml.state_norm_scale(lattice, fmap, S))
        out["tile_state_cells"] = cell_report["state_cells"]
        n = rows.size
        tile_label = np.full(n * ny, NOT_COMPUTED, np.int32)
        tile_label[chosen] = np.where(labels >= A, -1, labels)
        tile_periods = np.zeros(n * ny, np.int32)
        tile_periods[chosen] = periods
        out["tile_label"][:n] = tile_label.reshape(n, ny)
        out["tile_periods"][:n] = tile_periods.reshape(n, ny)
        for a, att in enumerate(atts[:A]):
            out["tile_attractor_point"][a, :att.period] = modal_section(fmap, att.points)
            out["tile_attractor_period"][a] = att.period
            out["tile_attractor_amplitude"][a] = fmap.amplitude(att.points[0], att.period)
            out["tile_attractor_multiplier"][a] = np.max(np.abs(att.multipliers))
        mismatch = 0.0
        if atts and fmap is not full:  # the lean rule again, on the attractors found
            mismatch = fmap.acceleration_mismatch(full, np.concatenate([a.points for a in atts]))
        if mismatch > LEAN_RTOL:
            out["status"] = STATUS_NOT_CONVERGED
            out["message"] = (f"the {fmap.radial_points}-point radial rule chosen on the window's trajectories "
                              f"differs by {mismatch:.1e} from the full rule on the attractors found (they lie "
                              f"beyond what the window's trajectories visit; method = \"brute\" keeps the full rule)")
        elif len(atts) > A or np.any(labels < 0):
            out["status"] = STATUS_NOT_CONVERGED
            out["message"] = (f"more than max_attractors = {A} attractors (raise max_attractors)" if len(atts) > A
                              else f"initial conditions unclassified after max_periods = "
                                   f"{options.settings.max_periods} (label -1)")
        return out

    def warmups(self, options: BasinsOptions) -> list[Callable[[], None]]:
        # the classifier's kernel, and the attractors' (Newton search, amplitude): about
        # 3 s and 2.5 s of compilation for one mode, in parallel on two ranks
        if not options.rom_kernels:
            return []
        return [partial(_compile_classifier, options), partial(_compile_attractor_tools, options)]

    def assemble(self, raw, options: BasinsOptions):
        import xarray as xr

        grid_dims = [d for d in raw["tile_label"].dims if d in GRID_KEYS]
        gshape = tuple(raw.sizes[d] for d in grid_dims)
        nx, ny, A = options.ic_x[2], options.ic_y[2], options.max_attractors
        P, S = options.settings.max_period, options.n_state
        lattice = options.lattice()
        scale = ml.lattice_scale(lattice, S)
        label = np.full((*gshape, nx, ny), NOT_COMPUTED, np.int32)
        points = np.full((*gshape, A, P, S), np.nan)
        period = np.zeros((*gshape, A), np.int32)
        amp = np.full((*gshape, A), np.nan)
        mult = np.full((*gshape, A), np.nan)
        frac = np.full((*gshape, A), np.nan)
        intf = np.full((*gshape, A), np.nan)
        n_att = np.zeros(gshape, np.int32)
        uncl = np.full(gshape, np.nan)
        order = [*grid_dims, "subtask"]
        tl = raw["tile_label"].transpose(*order, "tile_row", "ic_y").values
        tp = raw["tile_attractor_point"].transpose(*order, ...).values
        tper = raw["tile_attractor_period"].transpose(*order, ...).values
        tamp = raw["tile_attractor_amplitude"].transpose(*order, ...).values
        tmul = raw["tile_attractor_multiplier"].transpose(*order, ...).values
        for g in np.ndindex(*gshape):
            if np.all(tl[g] == NOT_COMPUTED):
                continue
            tiles = [[(ma.Attractor(tp[g][t, a, :int(tper[g][t, a])], np.array([tmul[g][t, a]])),
                       tamp[g][t, a]) for a in range(A) if tper[g][t, a] > 0]
                     for t in range(tl[g].shape[0])]
            merged, index = ma.merge_attractors(tiles, scale, options.settings.radius)
            lab = np.full((nx, ny), -1, np.int32)
            for t, idx in enumerate(index):
                rows = options.tile_rows(t)
                tile = tl[g][t, :rows.size]
                if np.all(tile == NOT_COMPUTED):  # a tile not computed (yet): not unclassified
                    lab[rows] = NOT_COMPUTED
                    continue
                lut = np.full(A + 1, -1, np.int32)
                lut[:idx.size] = np.where(idx < A, idx, -1)
                unlabelled = np.where(tile == NOT_COMPUTED, NOT_COMPUTED, -1)  # not in the sample, or unclassified
                lab[rows] = np.where(tile >= 0, lut[np.clip(tile, 0, A)], unlabelled)
            label[g] = lab
            n_att[g] = min(len(merged), A)
            computed = lab[lab != NOT_COMPUTED]
            uncl[g] = float(np.mean(computed == -1))
            for r, (att, a_amp) in enumerate(merged[:A]):
                k = att.period
                points[g][r, :k] = att.points
                period[g][r] = k
                amp[g][r] = a_amp
                mult[g][r] = att.multipliers[0]
                frac[g][r] = global_integrity_measure(computed, r)
                if options.sample is None:
                    proj = att.points[:, [lattice.ix, lattice.iy]]
                    intf[g][r] = integrity_factor(lab, lattice.x, lattice.y, proj, r)
        status = None
        if "status" in raw:  # a missing tile makes the point missing, else the worst tile's status
            st = raw["status"]
            status = xr.where((st == -1).any("subtask"), -1, st.max("subtask")).astype(np.int8).values
        G = tuple(grid_dims)
        K = len(options.modes)
        data = {
            "label": (G + ("ic_x", "ic_y"), label, {
                "units": "1", "long_name": "attractor index of the initial condition",
                "flag_values": np.array([-2, -1], np.int32),
                "flag_meanings": "not_computed unclassified",
                "lattice_mode": np.int32(options.lattice_mode - 1)}),
            "basin_fraction": (G + ("attractor",), frac, {
                "units": "1", "long_name": "global integrity measure: basin area fraction of "
                "the lattice window (Soliman and Thompson 1989; of the sample with basins.sample)"}),
            "integrity_factor": (G + ("attractor",), intf, {
                "units": "1", "long_name": "integrity factor: radius of the largest disc "
                "centred at the attractor inside its basin, window scaled to the unit square, "
                "over 1/2 (Lenci and Rega 2003)"}),
            "attractor_amplitude": (G + ("attractor",), amp, {
                "units": "m", "long_name": "max |w(0.5 Re, 0, t)| on the attractor"}),
            "attractor_period": (G + ("attractor",), period, {
                "units": "1", "long_name": "attractor period in forcing periods (0: none)"}),
            "attractor_multiplier": (G + ("attractor",), mult, {
                "units": "1", "long_name": "largest Floquet multiplier modulus"}),
            "attractor_coordinate": (G + ("attractor", "phase", "mode"), points[..., :K], {
                "units": "m", "long_name": "modal coordinates q_mn of the attractor's Poincare points"}),
            "attractor_velocity": (G + ("attractor", "phase", "mode"), points[..., K:], {
                "units": "m s-1", "long_name": "modal velocities dq_mn/dt of the attractor's Poincare points"}),
            "n_attractors": (G, n_att, {"units": "1", "long_name": "attractors found"}),
            "rk4_steps": (G, raw["tile_rk4_steps"].transpose(*order).values.max(axis=-1).astype(np.int32), {
                "units": "1", "long_name": "RK4 steps per forcing period"}),
            "radial_points": (G, raw["tile_radial_points"].transpose(*order).values.max(axis=-1).astype(np.int32), {
                "units": "1", "long_name": "radial Gauss-Legendre points of the ROM (model.rom.lean_radial_points)"}),
            "state_cells": (G, raw["tile_state_cells"].transpose(*order).values.max(axis=-1).astype(np.int32), {
                "units": "1", "long_name": "most cells in a tile's state-space cell map (states of more than "
                "two coordinates)",
                "state_cell_limit": np.int32(mc.state_cell_limit()),
                "comment": "at state_cell_limit a map takes no new cells: its tile's last trajectories ran longer "
                           "(labels still from labelled cells, capture and Newton); a coarser cell_resolution "
                           "or more tiles keep it below"}),
            "unclassified_fraction": (G, uncl, {
                "units": "1", "long_name": "fraction of the lattice with label -1"}),
        }
        if status is not None:
            data["status"] = (G, status, raw["status"].attrs)
        if "message" in raw:
            tiles = raw["message"].transpose(*order).values
            joined = np.empty(gshape, dtype=object)
            for g in np.ndindex(*gshape):
                joined[g] = "; ".join(dict.fromkeys(m for m in tiles[g] if m))
            data["message"] = (G, joined, raw["message"].attrs)
        coords = {d: raw[d] for d in grid_dims if d in raw.coords}
        coords.update({
            "ic_x": ("ic_x", lattice.x, {"units": "m", "long_name":
                                         f"initial displacement of mode {self._mode(options)}"}),
            "ic_y": ("ic_y", lattice.y, {"units": "m s-1", "long_name":
                                         f"initial velocity of mode {self._mode(options)}"}),
            "attractor": ("attractor", np.arange(A, dtype=np.int32), {
                "units": "1", "long_name": "attractor index, by decreasing amplitude"}),
            **opt.mode_coords(options.modes),
        })
        return xr.Dataset({k: xr.Variable(*v) for k, v in data.items()}, coords=coords,
                          attrs=dict(raw.attrs))

    @staticmethod
    def _mode(options) -> str:
        m, n = options.modes[options.lattice_mode - 1]
        return f"({m}, {n})"


BASINS = Basins()


def _warmup_map(options: BasinsOptions) -> ForcedMap:
    # The stroboscopic map of the job's ROM at a Fig. 19a point, for the warmup calls
    rom = rom_for(Membrane(law=options.material), options.prestretch, options.modes)
    return ForcedMap.from_loading(rom, Loading(33.5, 1.0, 0.05), options.steps or mb.DEFAULT_STEPS)


def _compile_classifier(options: BasinsOptions) -> None:
    # Basins.warmups: the lattice classifier's kernel
    lattice = ml.Lattice(np.array([0.0, 0.01]), np.array([0.0, 0.1]), 0, len(options.modes))
    mb.classify_lattice(ml.lattice_states(lattice, slice(None), options.n_state)[:1], lattice,
                        _warmup_map(options), mb.Settings(max_periods=2), use_cells=options.method == "fast")


def _compile_attractor_tools(options: BasinsOptions) -> None:
    # Basins.warmups: the Newton search and the amplitude of attractors
    fmap = _warmup_map(options)
    fmap.amplitude(np.zeros(options.n_state))
    ma.find_periodic_orbit(np.zeros(options.n_state), 1, fmap, np.ones(options.n_state), 1e-8, max_iter=1)
