"""Model files named by package: ``satkit:<file>`` entries of a force configuration.

The gravity field, ocean tide model, space weather and ephemeris of a campaign may name a file
shipped in the satkit-data package (``satkit:EGM96.gfc``); the script boundary resolves them
to installed paths once, before the settings reach the library.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["resolve_model_paths"]

_PACKAGE_PREFIX = "satkit:"


_PATH_KEYS = {"field", "ocean", "space_weather", "ephemeris"}


def _package_file(name: str) -> str:
    import satkit_data

    path = Path(satkit_data.__file__).resolve().parent / "data" / name
    if not path.exists():
        raise FileNotFoundError(f"satkit-data has no file '{name}'")
    return str(path)


def resolve_model_paths(forces: dict) -> dict:
    """Force configuration with ``satkit:<file>`` entries replaced by installed file paths.

    Parameters
    ----------
    forces : dict
        Sections of :func:`leopod.dynamics.force_config.build_force_model`; the keys
        ``field``, ``ocean``, ``space_weather`` and ``ephemeris`` may name a file of the
        satkit-data package as ``satkit:EGM96.gfc``.

    Returns
    -------
    dict
        A copy with resolved paths (other values unchanged).
    """
    out = {}
    for name, section in forces.items():
        if isinstance(section, dict):
            section = {k: (_package_file(v[len(_PACKAGE_PREFIX):])
                           if k in _PATH_KEYS and isinstance(v, str)
                           and v.startswith(_PACKAGE_PREFIX) else v)
                       for k, v in section.items()}
        out[name] = section
    return out
