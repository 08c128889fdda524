"""Every GLSL function that has a float64 twin, held to it by one harness (DESIGN.md: one
physical function has one GLSL home and one float64 twin, the GLSL function names its twin).

The ``// twin:`` annotations of the shader library say which Python object each function
follows and on which inputs (tests/glsl_twins.py reads them). Each one is a test case here:
the function runs on the GPU (llvmpipe) over a grid of float32 inputs, its twin in float64 on
the same inputs, and the two agree within the case's tolerance.

Tolerances: the inputs are the same float32 numbers on both sides, so what remains is the
shader's float32 arithmetic. A chain of a few roundings costs a few 1e-7 relative; Mesa's
transcendental functions (exp2/log2 behind pow and exp, sin, cos, atan) are good to a few
ulps; ``DEFAULT_RTOL`` = 1e-5 covers those with margin. Ill-conditioned cases get their own
tolerance below, each with the reason (cancellation in a difference, an error amplified by a
steep function). Measured errors: ``pytest -s`` prints each case's largest.
"""

from __future__ import annotations

import ast
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest

from skydome.astro.photometry import mag_to_optical_depth
from skydome.atmosphere.inputs import (
    geometry_inputs,
    mie_lobe_uniforms,
    mie_phase_defines,
    profile_defines,
    spectra_inputs,
)
from skydome.celestial.sun import limb_uniforms
from skydome.clouds.direction_table import table_frame
from skydome.core.cameras import CubemapCamera, EquirectCamera, FisheyeCamera, PerspectiveCamera
from skydome.core.refraction_table import RefractionTable
from skydome.display.tonemap import FILMIC_DESATURATION_STOPS, FILMIC_INPUT_CAP, TONEMAPS
from skydome.night.airglow import AIRGLOW_HEIGHT_M, EARTH_RADIUS_M
from skydome.night.light_pollution import DEFAULT_EXTINCTION_MAG
from skydome.spectra import SRGB_LUMINANCE
from tests.glsl_twins import (
    POINTS,
    Twin,
    environment,
    fibonacci_sphere,
    find_twins,
    flatten,
    make_inputs,
    resolve,
    run_gpu,
)

DEFAULT_RTOL = 1e-5
DEFAULT_ATOL = 0.0


@dataclass
class Setup:
    """What a case needs beyond its annotation (all optional).

    ``uniforms``, ``defines``: added to the annotation's (a callable is called first, for
    values made by production code); ``textures(ctx)``: sampler uniforms; ``inputs()``:
    replaces the annotation's inputs; ``call(twin, **env)``: calls the resolved twin itself
    and returns outputs in the GLSL function's order (argument conversions, an instance);
    ``mask(env, ref)``: the points to compare (default: where the twin's result is finite)."""

    uniforms: object = field(default_factory=dict)
    defines: object = field(default_factory=dict)
    textures: object = None
    inputs: object = None
    call: object = None
    mask: object = None
    rtol: float = DEFAULT_RTOL
    atol: float = DEFAULT_ATOL


# ---------------------------------------------------------------------------- helpers

#: Wavelengths of the spectral cases: two groups of 4.
WAVELENGTHS_NM = np.linspace(400.0, 700.0, 8)


def _group(values, g):
    """Per point, the 4 values (M, 4) of wavelength group g (M,) of values (M, 4 groups)."""
    v = np.asarray(values).reshape(len(g), -1, 4)
    return v[np.arange(len(g)), np.asarray(g)]


def _unit_rows(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _directions_near(centre, max_angle_rad: float, n: int = 64) -> np.ndarray:
    """n x n unit vectors on a grid of the tangent plane at ``centre`` within +-tan(max_angle)."""
    c = _unit_rows(np.asarray(centre, float))
    e1 = _unit_rows(np.cross(c, [0.0, 0.0, 1.0]))
    e2 = np.cross(c, e1)
    t = np.linspace(-1.0, 1.0, n) * math.tan(max_angle_rad)
    x, y = (a.ravel()[:, None] for a in np.meshgrid(t, t))
    return _unit_rows(c + x * e1 + y * e2)


#: The Sun's sine of angular radius, and a centre for the sphere cases.
SIN_SUN = 0.0047
CENTRE = _unit_rows(np.array([0.3, -0.5, 0.8]))


def _near_sphere(span: float = 2.0):
    """Directions within ``span`` disk radii (on the tangent plane's square) of CENTRE."""
    d = _directions_near(CENTRE, span * SIN_SUN)
    return {
        "dir": d,
        "centre": np.broadcast_to(CENTRE, d.shape),
        "sin_radius": np.full(len(d), SIN_SUN),
    }


def _as_f32(inputs):
    return {k: np.asarray(v, np.float32).astype(np.float64) for k, v in inputs.items()}


def _refraction(twin, h, scale):
    """A refraction law of physics.refraction (arcmin, of an altitude in deg, at the weather
    whose factor is ``scale``) in the shaders' units: rad of rad."""
    return np.radians(twin(np.degrees(h), 1010.0 * scale, 10.0) / 60.0)


def _airless(k, d):
    """d + k (z d - up): the airless direction of unit apparent directions d (unnormalised)."""
    up = np.array([0.0, 0.0, 1.0])
    return d + k[:, None] * (d[:, 2:3] * d - up)


# ---------------------------------------------------------------------------- cameras

CAMERAS = {
    "perspective": (
        PerspectiveCamera(fov_deg=70.0, yaw_deg=120.0, pitch_deg=25.0, roll_deg=10.0),
        64,
        48,
    ),
    "fisheye": (FisheyeCamera(), 64, 64),
    "equirect": (EquirectCamera(), 64, 32),
    "cubemap": (CubemapCamera(), 6 * 16, 16),
}


def _pixel_centres(w, h):
    y, x = np.mgrid[0:h, 0:w] + 0.5
    return {"tile_xy": np.stack([x.ravel(), y.ravel()], axis=-1)}


def _camera_setup(name: str, **kw) -> Setup:
    cam, w, h = CAMERAS[name]
    uniforms = cam.inputs(w, h).values()
    return Setup(uniforms=uniforms, defines={"CAMERA_MODEL": cam.model}, **kw)


def _camera_ray(name):
    cam, w, h = CAMERAS[name]

    def call(twin, tile_xy, **_):
        d, ok = getattr(cam, twin.__name__)(tile_xy[:, 0], tile_xy[:, 1], w, h)
        return ok, d

    # The direction only where the pixel sees the sky (camera.glsl leaves the zenith else).
    def mask(env, ref):
        return np.concatenate([np.ones_like(ref[:, :1]), np.repeat(ref[:, :1] > 0.5, 3, 1)], 1)

    # float32 trigonometry: a few 1e-6 per component (as tests/test_projection.py).
    return _camera_setup(name, inputs=lambda: _pixel_centres(w, h), call=call, mask=mask, atol=5e-6)


def _face_margin(d):
    """How far a direction is from a cube face's edge: the largest |component| less the next."""
    a = np.sort(np.abs(d), axis=-1)
    return a[:, 2] - a[:, 1]


def _camera_project(name):
    cam, w, h = CAMERAS[name]

    def call(twin, dir, **_):
        x, y, ok = getattr(cam, twin.__name__)(dir, w, h)
        return ok, x, y

    def mask(env, ref):
        d = env["dir"]
        ok_clear = np.ones(len(d), bool)  # directions where "seen" is not decided by rounding
        if name == "perspective":
            ok_clear = np.abs(d @ cam.basis()[:, 2]) > 1e-5
        if name == "fisheye":
            ok_clear = np.abs(d[:, 2]) > 1e-5
        pos = ref[:, 0] > 0.5
        if name == "perspective":  # off the frame's plane far to the side: huge positions
            pos &= d @ cam.basis()[:, 2] > 0.05
        if name == "equirect":  # the seam at azimuth 0 = 2 pi
            pos &= np.minimum(ref[:, 1], w - ref[:, 1]) > 1e-3
        if name == "cubemap":  # an edge between faces
            pos &= _face_margin(d) > 1e-5
        return np.stack([ok_clear, pos, pos], axis=1)

    # Positions in pixels of 64-pixel frames: float32 atan / division, ~1e-4 px.
    return _camera_setup(name, call=call, mask=mask, rtol=1e-5, atol=1e-3)


def _solid_angle(name):
    cam, w, h = CAMERAS[name]

    def call(twin, dir, **_):
        return getattr(cam, twin.__name__)(dir, w, h)

    def mask(env, ref):  # where the camera sees: in front of the pinhole, above the horizon
        if name == "perspective":  # f^3 of a float32 cosine f: 2e-7 / f relative
            return (env["dir"] @ cam.basis()[:, 2] > 0.05)[:, None]
        if name == "fisheye":
            return (env["dir"][:, 2] > 0.0)[:, None]
        return np.ones_like(ref, bool)

    def inputs():  # the directions the camera sees, and a margin
        d = fibonacci_sphere(POINTS)
        if name == "perspective":
            d = fibonacci_sphere(4 * POINTS)
            d = d[d @ cam.basis()[:, 2] > 0.0][:POINTS]
        if name == "fisheye":
            d = fibonacci_sphere(2 * POINTS)[: POINTS + POINTS // 8]
        return {"dir": np.asarray(d, np.float32).astype(np.float64)}

    # As tests/test_projection.py: float32 trigonometry of a float32 direction.
    return _camera_setup(name, call=call, mask=mask, inputs=inputs, rtol=2e-5)


# ---------------------------------------------------------------------------- the atmosphere


def _atmosphere(name):
    from skydome.atmosphere import preset

    return preset(name)


def _densities(name):
    params = _atmosphere(name)
    return Setup(
        uniforms=lambda: geometry_inputs(params).values(),
        defines=lambda: profile_defines(params),
        call=lambda twin, altitude, **_: twin(params, altitude * 1000.0),
        # exp of float32 arguments of up to ~80 (the aerosol at 100 km), and ln densities
        # interpolated in float32: ~1e-6 relative; 1e-7 absolute for the vanishing ones.
        rtol=1e-5,
        atol=1e-7,
    )


def _mie_lobes():
    params = _atmosphere("mars")
    return Setup(
        uniforms=lambda: mie_lobe_uniforms(params, WAVELENGTHS_NM),
        defines=lambda: mie_phase_defines(params),
        call=lambda twin, nu, g, **_: _group(twin(params.mie_phase, nu, WAVELENGTHS_NM), g),
        # HG lobes up to g = 0.95 or so: the cancellation of henyey_greenstein_phase.
        rtol=1e-4,
    )


def _optical_depth():
    params = _atmosphere("earth")
    coefficients = params.coefficients(WAVELENGTHS_NM)
    return Setup(
        uniforms=lambda: spectra_inputs(params, WAVELENGTHS_NM).values(),
        call=lambda twin, g, c, **_: _group(twin(coefficients, c * 1000.0), g),
    )


# Distances (km): r^2 ~ 4e7 km^2 holds ~5 km^2 of float32 rounding, which the square root
# turns into 5 / (2 sqrt(disc)) km: 0.025 km where disc > 1e4 km^2 (rays that graze a sphere,
# disc below that, are compared for their boolean only).
_DISTANCE_ATOL_KM = 0.03


def _disc(env, radius):
    r, mu = env["r"], env["mu"]
    return r * r * (mu * mu - 1.0) + radius * radius


def _ray_sphere_mask(env, ref):
    o, d = env["o"], env["d"]
    b = np.sum(o * d, axis=-1)
    disc = b * b - (np.sum(o * o, axis=-1) - env["radius"] ** 2)
    return np.repeat((np.abs(disc) > 1e4)[:, None], 2, 1)


# ---------------------------------------------------------------------------- post


def _tonemap(name):
    op = TONEMAPS[name]

    def call(twin, exposed, **_):
        return twin(exposed.reshape(-1, 1, 3), name, 1.0).reshape(-1, 3)

    return Setup(
        uniforms={
            **op.gl_uniforms(op.check_params({})),
            "u_luminance_weights": tuple(float(x) for x in SRGB_LUMINANCE),
        },
        defines={
            "TONEMAP_OPERATOR": op.gl_id,
            "FILMIC_INPUT_CAP": FILMIC_INPUT_CAP,
            "FILMIC_DESATURATION_STOPS": FILMIC_DESATURATION_STOPS,
        },
        call=call,
        # display values in [0, 1]: float32 exp, log and pow, a few ulps of 1.
        rtol=1e-5,
        atol=1e-6,
    )


_REFRACTION_TABLE = RefractionTable()


#: The fog's direction table of the case below: its size, and its frame for a light in the
#: south-east seen from 1 km up.
_TABLE_SIZE = (256.0, 128.0)
_TABLE_FRAME = table_frame((0.6, -0.6, 0.5), 6361.0, 6360.0)

#: Cases keyed by "file:function"; each maps variant names to a Setup.
SETUPS: dict[str, dict[str, Setup]] = {
    # d = 1 + g^2 - 2 g nu loses digits to cancellation near nu = 1 at |g| = 0.95:
    # d = 0.0025 from terms of order 2 carries 2 * 6e-8 / 0.0025 = 5e-5 relative, x 1.5 in
    # d^1.5.
    "common/phase_functions.glsl:henyey_greenstein_phase": {"": Setup(rtol=1e-4)},
    "common/phase_functions.glsl:cornette_shanks_phase": {"": Setup(rtol=1e-4)},
    "common/mie_phase.glsl:mie_phase_group": {"mars": _mie_lobes()},
    # Refraction (rad): float32 tan of the law's argument; the laws vanish at the zenith,
    # where the shader's (unclamped) value is ~1e-9 rad below 0.
    "common/refraction.glsl:refraction_saemundsson": {
        "": Setup(
            call=lambda twin, h_true, u_refraction_scale, **_: _refraction(
                twin, h_true, u_refraction_scale
            ),
            rtol=1e-5,
            atol=1e-9,
        )
    },
    "common/refraction.glsl:refraction_bennett": {
        "": Setup(
            call=lambda twin, h_apparent, u_refraction_scale, **_: _refraction(
                twin, h_apparent, u_refraction_scale
            ),
            rtol=1e-5,
            atol=1e-9,
        )
    },
    # Unit directions: Mesa's atan (good to 3e-6 rad) for the elevation, float32 cos and sin.
    "common/refraction.glsl:airless_direction": {
        "": Setup(
            call=lambda twin, dir, u_refraction_scale, **_: _unit_rows(
                _airless(twin(dir[:, 2], u_refraction_scale), dir)
            ),
            atol=5e-6,
        )
    },
    # The table read by the texture unit: linear filtering with 8 bits of the fraction moves
    # k by 1/512 of a node step, < 1e-6 (k changes by < 2e-4 between nodes).
    "common/airless_table.glsl:airless_from_table": {
        "": Setup(
            textures=lambda ctx: _REFRACTION_TABLE.inputs(ctx, 1.0).values(),
            call=lambda twin, dir, **_: _airless(twin(dir[:, 2], 1.0), dir),
            atol=1e-6,
        )
    },
    "common/camera.glsl:camera_ray": {n: _camera_ray(n) for n in CAMERAS},
    "common/camera_project.glsl:camera_project": {n: _camera_project(n) for n in CAMERAS},
    "common/camera_project.glsl:camera_pixel_solid_angle": {n: _solid_angle(n) for n in CAMERAS},
    "common/atmosphere_common.glsl:densities": {
        "earth": _densities("earth"),  # tabulated air and ozone, a layered aerosol
        "earth_bruneton": _densities("earth_bruneton"),  # layered: exponentials and a tent
    },
    "common/atmosphere_common.glsl:distance_to_top": {
        "": Setup(atol=_DISTANCE_ATOL_KM, mask=lambda env, ref: _disc(env, 6420.0)[:, None] > 1e4)
    },
    "common/atmosphere_common.glsl:distance_to_bottom": {
        "": Setup(atol=_DISTANCE_ATOL_KM, mask=lambda env, ref: _disc(env, 6360.0)[:, None] > 1e4)
    },
    # Rays within 10 km^2 of the tangent may fall either way in float32.
    "common/atmosphere_common.glsl:ray_hits_ground": {
        "": Setup(mask=lambda env, ref: np.abs(_disc(env, 6360.0))[:, None] > 10.0)
    },
    "common/atmosphere_common.glsl:ray_sphere": {"": Setup(atol=0.05, mask=_ray_sphere_mask)},
    # Directions within 2 solar radii of a disk's centre. sin(theta) from a cross product of
    # float32 unit vectors: ~1e-7 absolute.
    # The lens of two disks in float32: 6e-6 of the disk's area near tangency and
    # containment, where the half-angles are computed from small differences of the radii
    # (1e-7 rad of 5e-3 rad); the fractions used (the Sun's, the Earth's shadow) need 1e-4.
    "common/eclipse.glsl:disk_overlap_fraction": {"": Setup(atol=2e-5)},
    "common/sphere_disk.glsl:sin_offset": {
        "": Setup(inputs=lambda: _as_f32(_near_sphere()), atol=2e-7)
    },
    "common/sphere_disk.glsl:ray_meets_sphere": {
        "": Setup(
            inputs=lambda: _as_f32(_near_sphere()),
            mask=lambda env, ref: (
                np.abs(np.linalg.norm(np.cross(env["dir"], env["centre"]), axis=-1) - SIN_SUN)
                > 1e-6
            )[:, None],
        )
    },
    # The normal is (t d - centre) / sin_radius: a difference of unit vectors, each off by
    # ~6e-8, divided by 0.0047; near the limb the root of sin_r^2 - sin^2 amplifies more.
    "common/sphere_disk.glsl:sphere_normal": {
        "": Setup(
            inputs=lambda: _as_f32(_near_sphere(1.0)),
            mask=lambda env, ref: np.repeat(
                (np.linalg.norm(np.cross(env["dir"], env["centre"]), axis=-1) < 0.99 * SIN_SUN)[
                    :, None
                ],
                3,
                1,
            ),
            atol=1e-4,
        )
    },
    "common/srgb.glsl:srgb_encode": {"": Setup(atol=1e-7)},
    # 9.65 - 10.3 exp(-0.6 d) cancels near its zero (d ~ 0.1 mm): float32's exp leaves ~1e-6
    # m/s there
    "weather/fall_speed.glsl:rain_fall_speed": {"": Setup(atol=1e-5)},
    "common/srgb.glsl:srgb_decode": {"": Setup(atol=1e-7)},
    "common/spectral.glsl:optical_depth": {"": _optical_depth()},
    "post/tonemap.glsl:tonemap_display_linear": {n: _tonemap(n) for n in TONEMAPS},
    "celestial/sun.glsl:limb_darkening": {
        "": Setup(
            uniforms=lambda: limb_uniforms(WAVELENGTHS_NM, 0.00465),
            call=lambda twin, mu, g, **_: _group(twin(mu[:, None], WAVELENGTHS_NM), g),
        )
    },
    "night/airglow.glsl:van_rhijn": {
        "": Setup(
            uniforms={
                "u_radius_ratio_sq": (EARTH_RADIUS_M / (EARTH_RADIUS_M + AIRGLOW_HEIGHT_M)) ** 2
            }
        )
    },
    # Near the horizon X = 1 / (cos z + 0.50572 (96.07995 - z_deg)^-1.6364) is steep in z_deg,
    # which the shader takes from a float32 acos: 4e-5 relative at z = 89 deg (measured).
    "night/light_pollution.glsl:airmass": {"": Setup(rtol=1e-4)},
    "night/light_pollution.glsl:slab": {
        "": Setup(
            rtol=1e-4,
            uniforms={"u_tau": float(mag_to_optical_depth(DEFAULT_EXTINCTION_MAG))},
            call=lambda twin, cos_z, **_: twin(np.arccos(cos_z), DEFAULT_EXTINCTION_MAG),
        )
    },
    # The square root of q's distance from the horizon amplifies float32's rounding of q
    # (~6e-8) near it: sqrt(6e-8) x 63 texels / 128 = 1.2e-4 of the texture, a sixtieth of a
    # texel; u wraps around at the light's azimuth (0 and 1 are one place).
    "clouds/direction_table.glsl:direction_table_uv": {
        "": Setup(
            uniforms={"u_table_frame": _TABLE_FRAME, "u_table_size": _TABLE_SIZE},
            call=lambda twin, d, **_: twin(d, _TABLE_SIZE, _TABLE_FRAME),
            # (and rays within float32's rounding of the horizon, whose half may differ)
            mask=lambda env, ref: (
                np.stack([np.abs(ref[:, 0] - 0.5) < 0.499, np.abs(ref[:, 1] - 0.5) > 1e-3], -1)
                & (np.abs(ref[:, 1] - 0.5) > 1e-3)[:, None]
            ),
            atol=3e-4,
        )
    },
    # Noise values within [-1, 1]: float32 lattice coordinates and fades, ~1e-6.
    "clouds/noise_common.glsl:perlin_fbm": {"": Setup(atol=1e-5)},
    "clouds/noise_common.glsl:worley_fbm": {"": Setup(atol=1e-5)},
}


def _setups(twin: Twin) -> dict[str, Setup]:
    return SETUPS.get(twin.key, {"": Setup()})


TWINS = find_twins()
CASES = [
    pytest.param(t, name, s, id=f"{t.key}[{name}]" if name else t.key)
    for t in TWINS
    for name, s in _setups(t).items()
]


def _value(v):
    return v() if callable(v) else v


@pytest.mark.parametrize(("twin", "variant", "setup"), CASES)
def test_glsl_function_matches_its_twin(ctx, twin, variant, setup):
    uniforms = {**twin.uniforms(), **_value(setup.uniforms)}
    defines = {**twin.defines(), **_value(setup.defines)}
    inputs = setup.inputs() if setup.inputs else make_inputs(twin)
    textures = setup.textures(ctx) if setup.textures else {}
    gpu = run_gpu(ctx, twin, inputs, defines, uniforms, textures)
    env = environment(twin, inputs, uniforms, defines)
    target = resolve(twin.target)
    if setup.call is not None:
        result = setup.call(target, **env)
    else:
        result = eval(f"_twin_({twin.args})", {**env, "_twin_": target})  # noqa: S307
    ref = flatten(result, len(gpu))
    keep = np.isfinite(ref)
    if setup.mask is not None:
        keep &= np.asarray(setup.mask(env, ref), bool).reshape(len(gpu), -1)
    assert keep.mean() > 0.5, "most points must be compared"
    err = np.abs(gpu - ref)[keep]
    scale = np.abs(ref)[keep]
    rel = err / np.maximum(scale, setup.atol / setup.rtol if setup.atol else 1e-300)
    print(f"\n{twin.key}[{variant}]: max abs {err.max():.3g}, max rel {rel.max():.3g}")
    np.testing.assert_allclose(gpu[keep], ref[keep], rtol=setup.rtol, atol=setup.atol)


def test_every_annotation_names_an_existing_twin():
    missing = []
    for t in TWINS:
        try:
            obj = resolve(t.target)
        except (ImportError, AttributeError) as exc:
            missing.append(f"{t.file}:{t.line} {t.target}: {exc}")
            continue
        if not callable(obj):
            missing.append(f"{t.file}:{t.line} {t.target} is not callable")
    assert not missing, "annotations naming no Python twin:\n" + "\n".join(missing)


def test_every_setup_belongs_to_an_annotation():
    keys = {t.key for t in TWINS}
    assert not sorted(set(SETUPS) - keys), "SETUPS entries without an annotated function"


#: A Python twin's docstring names its GLSL function: "GLSL twin: ``name``" (or "(GLSL:
#: ``name``)").
_CLAIM = re.compile(r"GLSL(?: twin)?:\s+``(\w+)``")


def test_every_claimed_twin_is_annotated():
    # The other direction: a module-level Python function whose docstring says it is a GLSL
    # function's twin must be named by that function's annotation, so the harness checks
    # the pair; the failure lists the pairs no annotation holds.
    import skydome

    root = Path(skydome.__file__).parent
    annotated = {(t.function, t.target) for t in TWINS}
    names = {t.function for t in TWINS}
    unannotated = []
    for path in sorted(root.rglob("*.py")):
        module = ".".join(path.relative_to(root.parent).with_suffix("").parts)
        for node in ast.parse(path.read_text()).body:
            if not isinstance(node, ast.FunctionDef):
                continue
            for glsl in _CLAIM.findall(ast.get_docstring(node) or ""):
                if (glsl, f"{module}.{node.name}") not in annotated:
                    why = "annotated with another twin" if glsl in names else "not annotated"
                    unannotated.append(f"{module}.{node.name} -> {glsl} ({why})")
    assert not unannotated, "twins the shaders do not name:\n" + "\n".join(unannotated)
