"""The resolution-model options of a range case: which model, and the TTP metric's inputs.

``--resolution-model`` takes a name of :data:`targetacq.core.cases.RESOLUTION_MODELS`
(``johnson``, ``mrtd``, ``ttp``; ``geometric`` is the former name of ``johnson``). Without it the
model is ``mrtd`` where an MRTD curve is given and ``johnson`` otherwise. The ``ttp`` model
takes the sensor's optics (``--aperture`` or ``--f-number`` with ``--wavelength``), its NETD
(``--netd``, which then goes into the TTP metric's noise instead of a separate SNR), the target's
ΔT and the options read here (jitter, smear, Cn², frame rate, scene contrast temperature), and
builds the :class:`targetacq.physics.ttp.TtpSystem` of the case (:func:`ttp_system`).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from targetacq.base.units import parse_quantity
from targetacq.core.cases import RESOLUTION_MODEL_ALIASES, RESOLUTION_MODELS
from targetacq.physics.ttp import TtpSystem

__all__ = ["TTP_OPTIONS", "read_resolution_model", "ttp_system"]

TTP_OPTIONS: Mapping[str, tuple[str, str, str]] = {
    # option: (TtpSystem field, quantity kind, valid)
    "jitter": ("jitter", "angle", ">= 0"),
    "smear": ("smear", "angle", ">= 0"),
    "cn2": ("cn2", "structure constant", ">= 0"),
    "frame_rate": ("frame_rate", "frequency", "> 0"),
    "scene_contrast": ("scene_contrast", "temperature difference", "> 0"),
}
"""The options that only the ``ttp`` resolution model reads."""


def read_resolution_model(
    options: Mapping[str, Any], numbers: Mapping[str, Any], noise: Mapping[str, Any]
) -> tuple[str, dict[str, float]]:
    """The resolution model asked for and the TTP numbers [SI] read from the options.

    Parameters
    ----------
    options : mapping
        ``resolution_model`` and the options of :data:`TTP_OPTIONS` as typed (text with
        units), None where not given.
    numbers : mapping
        The numbers read so far (the optics: ``aperture``, ``wavelength``).
    noise : mapping
        The sensor-noise keywords read so far (``contrast``, ``noise_equivalent_contrast``,
        ``mrtd``).

    Returns
    -------
    name : str
        A key of :data:`RESOLUTION_MODELS`.
    ttp : dict
        The TTP metric's numbers by :class:`TtpSystem` field (empty for another model).

    Raises
    ------
    ValueError
        An unknown model, a TTP option without ``--resolution-model ttp``, or what the chosen
        model needs and is not given, naming the options.

    Examples
    --------
    >>> read_resolution_model({"resolution_model": "ttp", "jitter": "0.05mrad"},
    ...     {"aperture": 0.05, "wavelength": 1e-5},
    ...     {"contrast": 2.0, "noise_equivalent_contrast": 0.05})
    ('ttp', {'jitter': 5e-05})
    """
    given = options.get("resolution_model")
    if given is None:
        name = "mrtd" if noise.get("mrtd") is not None else "johnson"
    else:
        name = RESOLUTION_MODEL_ALIASES.get(given, given)
        if name not in RESOLUTION_MODELS:
            raise ValueError(
                f"--resolution-model must be one of {', '.join(RESOLUTION_MODELS)}; got {given!r}"
            )
    ttp: dict[str, float] = {}
    for option, (field, kind, valid) in TTP_OPTIONS.items():
        text = options.get(option)
        if text is None:
            continue
        flag = "--" + option.replace("_", "-")
        if name != "ttp":
            raise ValueError(f"{flag} is used by --resolution-model ttp")
        value = parse_quantity(text, kind, flag)
        if not (value > 0 if valid == "> 0" else value >= 0):
            raise ValueError(f"{flag} must be {valid}; got {text!r}")
        ttp[field] = value
    if name == "mrtd" and noise.get("mrtd") is None:
        raise ValueError("--resolution-model mrtd needs an MRTD curve: --mrtd FILE")
    if name != "mrtd" and noise.get("mrtd") is not None:
        raise ValueError(f"--mrtd gives the mrtd resolution model, not {name}")
    if name == "ttp":
        missing = [
            flag
            for flag, present in (
                ("--aperture or --f-number, with --wavelength", "aperture" in numbers),
                ("--netd (0mK for none)", "noise_equivalent_contrast" in noise),
                ("--delta-t or the temperatures", "contrast" in noise),
            )
            if not present
        ]
        if missing:
            raise ValueError(f"--resolution-model ttp needs {'; '.join(missing)}")
    return name, ttp


def ttp_system(numbers: Mapping[str, Any], ifov: Any) -> TtpSystem:
    """The TTP system of a reading's numbers (floats or stacked arrays) and the sensor's IFOV.

    ``numbers`` holds ``aperture``, ``wavelength``, the NETD as ``ttp_netd`` and the fields read
    by :func:`read_resolution_model` (as ``ttp_<field>``).

    Examples
    --------
    >>> ttp_system({"aperture": 0.05, "wavelength": 1e-5, "ttp_netd": 0.05,
    ...             "ttp_jitter": 5e-5}, 2e-4).jitter
    5e-05
    """
    extra = {
        field: numbers[f"ttp_{field}"]
        for field, _, _ in TTP_OPTIONS.values()
        if f"ttp_{field}" in numbers
    }
    return TtpSystem(
        ifov=ifov,
        aperture=numbers["aperture"],
        wavelength=numbers["wavelength"],
        netd=numbers["ttp_netd"],
        **extra,
    )
