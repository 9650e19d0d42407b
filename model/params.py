"""Physical parameters of the membrane and of its loading.

Symbols follow the paper (Goncalves, Soares and Pamplona, IJSS 2011, sections 2-3):
``C1`` neo-Hookean constant (Eq. 1; the first constant of every material law,
:mod:`model.materials`, with ``C2`` of Mooney-Rivlin and ``Jm`` of Gent), ``h`` thickness, ``Gamma`` mass density, ``Re`` outer
radius, ``delta = Rf/Re`` radial stretch ratio and ``delta_o = Ro/Re`` inner radius ratio
(Eq. 20).  SI units throughout (docs/model.md, "Geometry, material and parameters").

Each field carries its units, long name and allowed range in its ``metadata``; the
records are the one source of those rules (the job files' validation and the result
files' attributes are derived from them: :func:`parameter_info`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

from .materials import LAW_CONSTANTS, LAWS, kernel_law


class ParameterError(ValueError):
    """An impossible parameter value.

    The message reads ``"<name> = <value> is invalid: must be <allowed>"``; the parts are
    kept as attributes so that callers (the job-file validation) can name the key their own
    way.
    """

    def __init__(self, name: str, value, allowed: str):
        self.name, self.value, self.allowed = name, value, allowed
        super().__init__(f"{name} = {value!r} is invalid: must be {allowed}")


def _parameter(default: float, units: str, long_name: str, low: float, *, low_open: bool,
               high: float | None = None, infinite: bool = False) -> float:
    """A dataclass field with its units, long name and range ``(low, high)`` in metadata
    (``infinite``: ``+inf`` allowed too)."""
    return field(default=default, metadata={"units": units, "long_name": long_name, "low": low,
                                            "low_open": low_open, "high": high, "infinite": infinite})


def _allowed(meta) -> str:
    if "choices" in meta:
        return "one of " + ", ".join(f'"{c}"' for c in meta["choices"])
    if meta["infinite"]:
        text = f"a number {'>' if meta['low_open'] else '>='} {meta['low']:g} or inf"
    elif meta["high"] is not None:
        text = f"a finite number in the open interval ({meta['low']:g}, {meta['high']:g})"
    else:
        text = f"a finite number {'>' if meta['low_open'] else '>='} {meta['low']:g}"
    return text if meta["units"] == "1" else f"{text} ({meta['units']})"


def _validate(record) -> None:
    """Convert integers to floats and check every field against its metadata range."""
    for f in fields(record):
        v = getattr(record, f.name)
        meta = f.metadata
        if "choices" in meta:
            if v not in meta["choices"]:
                raise ParameterError(f.name, v, _allowed(meta))
            continue
        if isinstance(v, int) and not isinstance(v, bool):
            v = float(v)
            object.__setattr__(record, f.name, v)
        ok = isinstance(v, float) and (math.isfinite(v) or (meta["infinite"] and v == math.inf)) and (
            v > meta["low"] if meta["low_open"] else v >= meta["low"]) and (
            meta["high"] is None or v < meta["high"])
        if not ok:
            raise ParameterError(f.name, v, _allowed(meta))


@dataclass(frozen=True)
class Membrane:
    """A pre-stretched hyperelastic annular membrane (neo-Hookean unless ``law`` says
    otherwise).

    Parameters
    ----------
    delta : float
        Radial stretch ratio ``Rf/Re`` (1), must be > 1 (at 1 every frequency is 0).
    delta_o : float
        Inner radius ratio ``Ro/Re`` (1), in (0, 1).
    C1 : float
        Neo-Hookean constant (Pa), Eq. (1): the first constant of every ``law``.
    h : float
        Undeformed thickness (m).
    Gamma : float
        Mass density (kg m-3); the mass per unit undeformed area is ``Gamma*h``.
    Re : float
        Undeformed outer radius (m).
    law : str
        Strain-energy law, a key of :data:`model.materials.LAWS`: ``"neo-hookean"`` (the
        paper's, default), ``"mooney-rivlin"`` or ``"gent"``.
    C2 : float
        Mooney-Rivlin constant (Pa), >= 0; only with ``law = "mooney-rivlin"`` (else 0).
    Jm : float
        Gent's limit of ``I1 - 3`` (1), > 0; only with ``law = "gent"`` (else inf; inf is
        the neo-Hookean limit).
    """

    delta: float = _parameter(1.1, "1", "radial stretch ratio Rf/Re", 1.0, low_open=True)
    delta_o: float = _parameter(0.2, "1", "inner radius ratio Ro/Re", 0.0, low_open=True, high=1.0)
    C1: float = _parameter(0.17e6, "Pa", "neo-Hookean constant", 0.0, low_open=True)
    h: float = _parameter(1e-3, "m", "undeformed thickness", 0.0, low_open=True)
    Gamma: float = _parameter(2200.0, "kg m-3", "mass density", 0.0, low_open=True)
    Re: float = _parameter(1.0, "m", "undeformed outer radius", 0.0, low_open=True)
    law: str = field(default="neo-hookean", metadata={"units": "", "long_name": "strain-energy law",
                                                      "choices": tuple(LAWS)})
    C2: float = _parameter(0.0, "Pa", "Mooney-Rivlin constant", 0.0, low_open=False)
    Jm: float = _parameter(math.inf, "1", "Gent limit of I1 - 3", 0.0, low_open=True, infinite=True)

    def __post_init__(self):
        _validate(self)
        for f in fields(self):
            owners = [law for law, constants in LAW_CONSTANTS.items() if f.name in constants]
            if owners and self.law not in owners and getattr(self, f.name) != f.default:
                raise ParameterError(f.name, getattr(self, f.name),
                                     f"left at {f.default:g} with law = {self.law!r} ({f.name} is a constant of "
                                     + " / ".join(f'"{k}"' for k in owners) + ")")

    @property
    def material(self):
        """The law with this membrane's constants, as the kernels take it
        (:func:`model.materials.kernel_law`)."""
        return kernel_law(self.law, self.C1, self.C2, self.Jm)

    @property
    def Ro(self) -> float:
        """Undeformed inner radius (m)."""
        return self.delta_o * self.Re

    @property
    def Rf(self) -> float:
        """Deformed outer radius (m)."""
        return self.delta * self.Re

    @property
    def wave_speed2(self) -> float:
        """``2 C1 / Gamma`` (m2 s-2): the factor between Galerkin eigenvalues and omega^2."""
        return 2.0 * self.C1 / self.Gamma

    def damping_rate(self, c):
        """``c / (Gamma h)`` (s-1): the damping coefficient of the modal equations.

        ``c`` (N s m-3, a float or an array) is the viscous pressure per unit undeformed
        area and velocity (docs/model.md, "Damping and forcing").
        """
        return c / (self.Gamma * self.h)


@dataclass(frozen=True)
class Loading:
    """Damping and harmonic pressure acting on the pre-stretched membrane (Eq. 24).

    Parameters
    ----------
    Omega : float
        Forcing frequency (rad s-1), > 0 (ignored when ``P0 == 0``).
    P0 : float
        Pressure amplitude (Pa), >= 0, on the projected area of the stretched membrane.
    c : float
        Viscous damping (N s m-3): pressure ``-c w_t`` per unit undeformed area, >= 0.
    """

    Omega: float = _parameter(1.0, "rad s-1", "forcing frequency", 0.0, low_open=True)
    P0: float = _parameter(0.0, "Pa", "forcing pressure amplitude", 0.0, low_open=False)
    c: float = _parameter(0.0, "N s m-3", "viscous damping coefficient per unit undeformed area",
                          0.0, low_open=False)

    def __post_init__(self):
        _validate(self)


def parameter_info(name: str) -> tuple[type, str, str]:
    """The record holding parameter ``name`` and the parameter's units and long name.

    Returns
    -------
    record : type
        :class:`Membrane` or :class:`Loading`.
    units, long_name : str
        CF ``units`` and ``long_name``.

    Raises
    ------
    KeyError
        If no record has a field ``name``.
    """
    for record in (Membrane, Loading):
        for f in fields(record):
            if f.name == name:
                return record, f.metadata["units"], f.metadata["long_name"]
    raise KeyError(name)
