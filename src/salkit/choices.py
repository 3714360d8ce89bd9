"""The allowed choices, named once: the scenario models, the command line, the algorithms and the
tests all read them from here. What is declared rather than listed (image formers, metrics, scene
object kinds, materials) is in :mod:`salkit.registry`."""
from .errors import ScenarioError

#: Image-formation accuracy: standard or high (for interferometry); what each level promises against
#: the exact matched filter, each former declares (:class:`salkit.focus.formers.FormerSpec`). The image
#: formers themselves are declared, not listed: :data:`salkit.registry.FORMERS`.
ACCURACY = ("standard", "high")
#: How the space-borne experiment stacks its sub-images.
STACK_MODES = ("incoherent", "coherent")
#: Turbulence models: phase-only screens along rays, or split-step wave optics (amplitude too).
ATMOSPHERE_MODELS = ("phase_screen", "wave_optics")
#: Amplitude windows.
WINDOWS = ("none", "hamming", "taylor")
#: Image planes of a grid.
PLANES = ("slant", "ground")
#: Autofocus methods: on the image (PGA, minimum entropy) or per pulse on the phase history.
AUTOFOCUS_METHODS = ("none", "pga", "min-entropy", "pulse")
#: Autofocus methods that work on a formed image.
IMAGE_AUTOFOCUS_METHODS = ("none", "pga", "min-entropy")
#: PGA phase-gradient kernels: phase difference, linear unbiased minimum variance, eigenvector.
PGA_KERNELS = ("pd", "lumv", "ev")
#: Nonlinear-chirp corrections from the reference channel.
CHIRP_CORRECTIONS = ("none", "resample", "deskew")
#: Laser phase-noise corrections: none, or the reference channel's per-pulse record removed.
PHASE_NOISE_CORRECTIONS = ("none", "reference")


def check_choice(field: str, value, allowed: tuple) -> None:
    """Raise :class:`~salkit.errors.ScenarioError` naming ``field`` unless ``value`` is allowed.

    Parameters
    ----------
    field : str
        Field or option name, for the message.
    value : object
    allowed : tuple of str

    Raises
    ------
    ScenarioError

    Examples
    --------
    >>> check_choice("--plane", "ground", PLANES)
    """
    if value not in allowed:
        raise ScenarioError(field, value, f"must be one of {', '.join(allowed)}")
