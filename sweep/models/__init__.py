"""Registry of models: ``[model] kind = name`` -> a :class:`~sweep.models.base.Model`.

The sweep builds the model of every grid point through this registry: ``"rom"``, the
Galerkin reduced-order model (:mod:`sweep.models.rom`), is the default; ``"full"``, the
membrane with its in-plane displacements (:mod:`sweep.models.full`), runs ``static`` and
``linear`` so far; ``"fe2d"``, the membrane on a two-dimensional finite-element mesh
(:mod:`sweep.models.fe2d`), checks it in ``linear``.  Models of one's
own are added through the environment variable ``SWEEP_EXTRA_MODELS``
(comma-separated ``name=module:attribute`` items, the module on ``PYTHONPATH``), as
``tests/escape_model.py`` adds Thompson's escape oscillator (docs/architecture.md).
"""

from __future__ import annotations

from sweep.models.base import Model
from sweep.registry import Registry

#: Environment variable with extra ``name=module:attribute`` entries.
EXTRA_ENV = "SWEEP_EXTRA_MODELS"

BUILTIN = {
    "rom": "sweep.models.rom:ROM",
    "full": "sweep.models.full:FULL",
    "fe2d": "sweep.models.fe2d:FE2D",
}

_REGISTRY = Registry("models", "model.kind", BUILTIN, EXTRA_ENV)


def registry() -> dict[str, str]:
    """The models available in this installation: ``name -> "module:attribute"``."""
    return _REGISTRY.entries()


def get(name: str) -> Model:
    """Import and return the model registered as ``name``.

    Raises
    ------
    JobError
        If no model of that name is available (the message lists those that are).
    TypeError
        If the entry is not a :class:`~sweep.models.base.Model`.
    """
    model = _REGISTRY.load(name)
    if not isinstance(model, Model):
        raise TypeError(f"{registry()[name]} is a {type(model).__name__}, not a Model")
    return model
