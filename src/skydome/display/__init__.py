"""Display: exposure (EV100 and automatic), tone mapping (NumPy reference and GLSL pass),
sRGB encoding and 8-bit quantization.

Typical use::

    scale = auto_exposure(frame, clip_percentile=99.5)   # or ev100_to_scale(14.5)
    scale = metered_exposure(frame, "spot")                # metering: eye, average, center
    image = tonemap(frame, "filmic", scale)                # uint8 (H, W, 3), NumPy float64
    image = gpu_tonemap(frame, "filmic", scale)            # same within 1 code value, on GL
"""

from skydome.display.exposure import (
    DEFAULT_KEY,
    DEFAULT_METERING,
    METERINGS,
    SATURATION_LUMINANCE_EV0,
    auto_exposure,
    ev100_to_scale,
    eye_key,
    log_average_luminance,
    metered_exposure,
    metered_luminance,
    scale_to_ev100,
)
from skydome.display.glare import DEFAULT_GLARE, GLARES, GpuGlare
from skydome.display.gpu_tonemap import GpuToneMapper, gpu_tonemap, read_rgb8, upload_frame
from skydome.display.srgb import quantize8, srgb_decode, srgb_encode
from skydome.display.tonemap import (
    DEFAULT_TONEMAP,
    TONEMAPS,
    ToneMapOperator,
    exponential,
    filmic,
    get_operator,
    hvs,
    hvs_coefficients,
    hvs_curve,
    linear,
    reinhard,
    reinhard_luminance,
    tonemap,
    tonemap_linear,
)

__all__ = [
    "DEFAULT_GLARE",
    "DEFAULT_KEY",
    "DEFAULT_METERING",
    "GLARES",
    "METERINGS",
    "GpuGlare",
    "eye_key",
    "metered_exposure",
    "metered_luminance",
    "DEFAULT_TONEMAP",
    "SATURATION_LUMINANCE_EV0",
    "TONEMAPS",
    "GpuToneMapper",
    "ToneMapOperator",
    "auto_exposure",
    "ev100_to_scale",
    "exponential",
    "filmic",
    "get_operator",
    "gpu_tonemap",
    "hvs",
    "hvs_coefficients",
    "hvs_curve",
    "linear",
    "log_average_luminance",
    "quantize8",
    "read_rgb8",
    "reinhard",
    "reinhard_luminance",
    "scale_to_ev100",
    "srgb_decode",
    "srgb_encode",
    "tonemap",
    "tonemap_linear",
    "upload_frame",
]
