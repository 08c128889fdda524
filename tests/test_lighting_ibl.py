"""Image-based lighting from the sky (skydome.lighting_ibl, `Lighting.prefiltered`,
`skydome lighting -o env.dds --brdf-table`): the prefiltered GGX cube map against the map it
comes from and a float64 twin of its shader, the BRDF table against an independent
quadrature and published values, the DDS file against a reader written from Microsoft's
layout, and the command line."""

from __future__ import annotations

import math
import struct

import numpy as np
import pytest

from skydome.errors import ParameterError
from skydome.io.dds import dds_cube_bytes
from skydome.lighting import map_samples
from skydome.lighting_ibl import (
    LAST_FACE_SIZE,
    MIN_ROWS,
    brdf_table,
    chain_length,
    cube_directions,
    cube_texel_solid_angles,
    prefilter,
)
from skydome.physics import ggx
from tests.cli_helpers import run_cli
from tests.test_viewer_soak import live_gl_objects

# -- an independent reader of the DDS files (Microsoft's "DDS file layout", DDS_HEADER and
# DDS_HEADER_DXT10 pages: a 4-byte magic, a 124-byte header, a 20-byte extension, then each
# face with its mip levels, largest first)


def read_dds_cube(blob: bytes) -> dict:
    assert blob[:4] == b"DDS "
    size, flags, height, width, pitch, depth, mips = struct.unpack_from("<7I", blob, 4)
    pf_size, pf_flags, fourcc = struct.unpack_from("<II4s", blob, 4 + 72)
    caps, caps2 = struct.unpack_from("<II", blob, 4 + 104)
    dxgi, dimension, misc, array_size, misc2 = struct.unpack_from("<5I", blob, 128)
    faces = [[] for _ in range(6)]
    offset = 148
    for f in range(6):
        for k in range(mips):
            m = max(width >> k, 1)
            count = m * m * 4
            faces[f].append(np.frombuffer(blob, "<f2", count, offset).reshape(m, m, 4))
            offset += 2 * count
    return {
        "size": size, "flags": flags, "width": width, "height": height, "pitch": pitch,
        "mips": mips, "pf_size": pf_size, "pf_flags": pf_flags, "fourcc": fourcc,
        "caps": caps, "caps2": caps2, "dxgi": dxgi, "dimension": dimension, "misc": misc,
        "array_size": array_size, "faces": faces, "end": offset, "length": len(blob),
    }  # fmt: skip


# -- float64 twin of shaders/lighting/prefilter_ggx.glsl (GL's sampling written out: a 2x2
# box mip chain, bilinear with texel centres at (i + 0.5) / size, u repeated, v clamped,
# linear between levels)


def weighted_map64(radiance: np.ndarray) -> np.ndarray:
    h = radiance.shape[0]
    w = np.cos((0.5 - (np.arange(h) + 0.5) / h) * math.pi)[:, None, None]
    return np.concatenate([radiance * w, np.broadcast_to(w, (*radiance.shape[:2], 1))], -1)


def mip_chain(tex: np.ndarray) -> list[np.ndarray]:
    chain = [tex]
    while max(chain[-1].shape[:2]) > 1:
        a = chain[-1]
        h, w = a.shape[:2]
        if h > 1:
            a = 0.5 * (a[0::2] + a[1::2])
        if w > 1:
            a = 0.5 * (a[:, 0::2] + a[:, 1::2])
        chain.append(a)
    return chain


def bilinear(level: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    h, w = level.shape[:2]
    x, y = u * w - 0.5, v * h - 0.5
    x0, y0 = np.floor(x), np.floor(y)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]
    xi0, xi1 = x0.astype(int) % w, (x0.astype(int) + 1) % w
    yi0, yi1 = np.clip(y0.astype(int), 0, h - 1), np.clip(y0.astype(int) + 1, 0, h - 1)
    return (
        level[yi0, xi0] * (1 - fx) * (1 - fy) + level[yi0, xi1] * fx * (1 - fy)
        + level[yi1, xi0] * (1 - fx) * fy + level[yi1, xi1] * fx * fy
    )  # fmt: skip


def equirect_uv(d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    az = np.arctan2(d[..., 0], d[..., 1])
    return np.mod(az / (2 * math.pi), 1.0), np.arctan2(
        np.hypot(d[..., 0], d[..., 1]), d[..., 2]
    ) / math.pi


def radiance_at(chain, d, lod) -> np.ndarray:
    u, v = equirect_uv(d)
    lod = np.asarray(lod, dtype=np.float64) * np.ones(u.shape)
    top = len(chain) - 1
    l0 = np.clip(np.floor(lod).astype(int), 0, top)
    l1 = np.minimum(l0 + 1, top)
    f = (lod - l0)[..., None]
    out = np.zeros((*u.shape, 4))
    for k in range(top + 1):
        for lk, wk in ((l0, 1 - f), (l1, f)):
            sel = lk == k
            if np.any(sel):
                out[sel] += wk[sel] * bilinear(chain[k], u[sel], v[sel])
    return out[..., :3] / out[..., 3:]


def prefilter_twin(radiance: np.ndarray, face_size: int, samples: int) -> list[np.ndarray]:
    h, w = radiance.shape[:2]
    chain = mip_chain(weighted_map64(radiance))
    max_lod = max(math.log2(h / MIN_ROWS), 0.0)
    texel_sr = (2 * math.pi / w) * (math.pi / h)
    xi = ggx.hammersley(samples)
    out = []
    for k in range(chain_length(face_size)):
        m = face_size >> k
        alpha = (k / (chain_length(face_size) - 1)) ** 2
        n = cube_directions(m).reshape(-1, 3)
        if k == 0:
            out.append(radiance_at(chain, n, 0.0).reshape(6, m, m, 3))
            continue
        acc, weight = np.zeros((len(n), 3)), np.zeros(len(n))
        for x in xi:
            hv = ggx.importance_sample_ggx(np.broadcast_to(x, (len(n), 2)), alpha, n)
            noh = np.sum(n * hv, -1)
            l_dir = 2 * noh[:, None] * hv - n
            nol = np.sum(n * l_dir, -1)
            ok = nol > 0
            pdf = 0.25 * ggx.d_ggx(noh[ok], alpha)
            lod = np.clip(0.5 * np.log2(1.0 / (samples * pdf) / texel_sr) + 1.0, 0.0, max_lod)
            acc[ok] += radiance_at(chain, l_dir[ok], lod) * nol[ok, None]
            weight[ok] += nol[ok]
        out.append((acc / weight[:, None]).reshape(6, m, m, 3))
    return out


def test_the_faces_are_the_file_formats_and_the_axes_east_up_north():
    # OpenGL 4.6 table 8.19 (D3D alike): +X's texel (s, t) = (0, 0) looks at (1, 1, 1)
    # in cube space (sc = -rz, tc = -ry); +Y's at (-1, 1, -1) (sc = rx, tc = rz); +Z's at
    # (-1, 1, 1) (sc = rx, tc = -ry). Cube space (east, up, north): ENU (x, z, y).
    d = cube_directions(2)
    # texel centres of a 2-texel face are at (sc, tc) = (-1/2, -1/2): (1, 1/2, 1/2) / |..|
    c = 1 / math.sqrt(1.5)
    assert np.allclose(d[0, 0, 0], np.array([1.0, 0.5, 0.5]) * c)  # +X: east, north, up
    assert np.allclose(d[2, 0, 0], np.array([-0.5, -0.5, 1.0]) * c)  # +Y = up: west, south
    assert np.allclose(d[4, 0, 0], np.array([-0.5, 1.0, 0.5]) * c)  # +Z = north: west, up
    centres = cube_directions(1)[:, 0, 0]
    assert np.allclose(centres, [[1, 0, 0], [-1, 0, 0], [0, 0, 1], [0, 0, -1], [0, 1, 0],
                                 [0, -1, 0]])  # fmt: skip
    omega = cube_texel_solid_angles(16)
    assert 6 * omega.sum() == pytest.approx(4 * math.pi, rel=1e-12)


def test_bad_settings_are_refused():
    for size in (0, 6, 100, 4096, True, 12.0):
        with pytest.raises(ParameterError, match="cube size"):
            prefilter(np.ones((8, 16, 3)), face_size=size)
    with pytest.raises(ParameterError, match="equirect"):
        prefilter(np.ones((8, 8, 3)))
    with pytest.raises(ParameterError, match="samples"):
        prefilter(np.ones((8, 16, 3)), samples=0)
    with pytest.raises(ParameterError, match="BRDF table size"):
        brdf_table(size=4)
    with pytest.raises(ParameterError, match="65504"):
        dds_cube_bytes([np.full((6, 4, 4, 3), 7e4)])


def synthetic_map(h: int = 32) -> np.ndarray:
    """A sky-like equirect map (cd/m^2): a bright band above the horizon, a dimmer zenith, a
    dark ground and a small bright spot (a few texels) to stress the mip selection."""
    el = (0.5 - (np.arange(h) + 0.5) / h) * math.pi
    az = (np.arange(2 * h) + 0.5) / (2 * h) * 2 * math.pi
    e, a = np.meshgrid(el, az, indexing="ij")
    base = np.where(e > 0, 2000.0 + 6000.0 * np.exp(-e / 0.3), 300.0)
    spot = 5e4 * np.exp(-(((e - 0.5) / 0.08) ** 2 + ((a - 2.5) / 0.08) ** 2))
    rgb = np.stack(
        [base * 0.8 + spot, base * 0.9 + spot, base * (1.2 - 0.3 * np.cos(a)) + spot], -1
    )
    return rgb


@pytest.mark.gl
def test_the_shader_equals_its_float64_twin(ctx):
    # A 16-texel cube (3 levels: 16, 8, 4 at roughness 0, 0.5, 1) of a 64 x 32 map, 64
    # samples a texel, against the twin above (the same Hammersley points, lods and GL
    # sampling in float64). What differs: float32 directions and texture coordinates (1e-7
    # of a texel) and the GPU's bilinear weights, which have 8 fractional bits (llvmpipe, as
    # most GPUs): an error up to 1/512 of the difference between neighbouring texels, 10 %
    # of the value near the spot here, so 2e-4 (measured 2.0e-4) at level 0, bounded by
    # 5e-4; at the rough levels those errors average out over the samples (measured 5e-6):
    # 5e-5.
    radiance = synthetic_map()
    got = prefilter(radiance, ctx, face_size=16, samples=64)
    want = prefilter_twin(radiance, 16, 64)
    assert len(got.levels) == 3 and got.roughness == (0.0, 0.5, 1.0)
    for k, (g, w) in enumerate(zip(got.levels, want, strict=True)):
        err = np.max(np.abs(g / w - 1.0))
        print(f"level {k}: {err:.2e}")
        assert err < (5e-4 if k == 0 else 5e-5), (k, err)


@pytest.fixture(scope="module")
def valletta_ibl():
    from skydome import Sky

    with Sky("Valletta", "2018-03-01T10:00") as sky:
        light = sky.lighting()
        ctx = sky.graph.ctx
        cube = light.prefiltered(ctx)
        with_sun = light.prefiltered(ctx, with_sun=True)
    return light, cube, with_sun


@pytest.mark.gl
def test_roughness_0_is_the_map_and_every_level_keeps_its_mean(valletta_ibl):
    light, cube, _ = valletta_ibl
    assert cube.face_size == 128 and len(cube.levels) == 6
    assert cube.levels[-1].shape == (6, LAST_FACE_SIZE, LAST_FACE_SIZE, 3)
    assert cube.roughness == pytest.approx([0, 0.2, 0.4, 0.6, 0.8, 1.0])
    data = np.asarray(light.sky_map.data[..., :3], dtype=np.float64)
    h, w = data.shape[:2]
    # Level 0 is the map read bilinearly at the texels' directions (weighted by the rows'
    # solid angles: still a convex combination): each value within the range of the map's
    # 2 x 2 texels around it (1e-6: float32), and within 1 % of the plain bilinear value
    # on average (the weights differ by cos(lat) between two rows: 1.4 deg apart).
    d = cube_directions(128).reshape(-1, 3)
    u, v = equirect_uv(d)
    x, y = u * w - 0.5, v * h - 0.5
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    corners = np.stack([data[np.clip(y0 + j, 0, h - 1), (x0 + i) % w] for i in (0, 1)
                        for j in (0, 1)])  # fmt: skip
    got = cube.levels[0].reshape(-1, 3)
    assert np.all(got >= corners.min(0) * (1 - 1e-6)) and np.all(got <= corners.max(0) * (1 + 1e-6))
    plain = bilinear(np.asarray(light.sky_map.data[..., :3], np.float64), u, v)
    assert np.mean(np.abs(got / plain - 1.0)) < 0.01
    # Every level's mean over the sphere (texels weighted by their exact solid angles) is
    # the map's mean: the GGX kernel is normalised and depends on n.l alone. Measured within
    # 0.3 % (the last, 0.14 %): the discrete samples and the mips' bilinear blends.
    radiance, _, omega = map_samples(light.sky_map)
    mean = radiance.T @ omega / (4 * math.pi)
    errors = [np.max(np.abs(cube.mean(k) / mean - 1.0)) for k in range(len(cube.levels))]
    print("level means - map mean:", np.round(errors, 5))
    assert errors[-1] < 0.005 and max(errors) < 0.005


@pytest.mark.gl
def test_with_the_sun_the_cube_holds_its_light(valletta_ibl):
    # The Sun added as a point source: each level's integral over the sphere (mean x 4 pi)
    # grows by the Sun's illuminance facing it, E (lx = cd/m^2 sr), to 1 % (measured
    # 0.002 % at level 0, where it is one texel, and 0.2-0.4 % at the others); at the last
    # (4 x 4 texels a face, roughness 1) to 2 %: there the Sun's term is a clamped cosine of
    # n.s, whose kink at 90 deg the 96 texel centres sum 1.4 % short.
    light, cube, with_sun = valletta_ibl
    e = np.asarray(light.sun.illuminance_rgb)
    for k in range(len(cube.levels)):
        added = (with_sun.mean(k) - cube.mean(k)) * 4 * math.pi
        tolerance = 0.02 if k == len(cube.levels) - 1 else 0.01
        assert added == pytest.approx(e, rel=tolerance), (k, added / e - 1)
    assert with_sun.with_sun and not cube.with_sun
    # At level 0 the Sun is one texel, the one whose direction is nearest to it (within half
    # a texel's diagonal: 0.5 deg at 128 texels a face, whose texels span 0.45-0.7 deg).
    diff = (with_sun.levels[0] - cube.levels[0]).sum(-1).reshape(-1)
    assert np.count_nonzero(diff > 1e3) == 1
    dirs = cube_directions(128).reshape(-1, 3)
    sun = np.asarray(light.sun.direction)
    assert np.argmax(diff) == np.argmax(dirs @ sun)


@pytest.mark.gl
def test_prefilter_and_table_release_their_gl_objects(ctx):
    before = live_gl_objects()
    prefilter(synthetic_map(16), ctx, face_size=8, samples=4)
    brdf_table(ctx, size=8, samples=4)
    assert live_gl_objects() == before


def table_by_quadrature(nov: float, roughness: float, n_theta: int = 3000, n_phi: int = 720):
    """(scale, bias) by the midpoint rule over the hemisphere of light directions l (theta,
    phi), with no sampling of the lobe: scale = int D G (1 - Fc) / (4 n.v) dl and bias the
    same with Fc, Fc = (1 - v.h)^5 (the BRDF D G F / (4 n.l n.v) times n.l, over F0)."""
    alpha = roughness**2
    theta = (np.arange(n_theta) + 0.5) / n_theta * 0.5 * math.pi
    phi = (np.arange(n_phi) + 0.5) / n_phi * math.pi  # symmetric about the plane of v: x2
    t, p = np.meshgrid(theta, phi, indexing="ij")
    l_dir = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1)
    v = np.array([math.sqrt(1 - nov * nov), 0.0, nov])
    h = l_dir + v
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    voh = h @ v
    d = ggx.d_ggx(h[..., 2], alpha)
    g = ggx.g_smith_schlick(nov, l_dir[..., 2], alpha)
    fc = (1 - voh) ** 5
    dl = 2 * np.sin(t) * (0.5 * math.pi / n_theta) * (math.pi / n_phi)
    base = d * g / (4 * nov) * dl
    return float(np.sum(base * (1 - fc))), float(np.sum(base * fc))


@pytest.fixture(scope="module")
def table(ctx):
    return brdf_table(ctx)


@pytest.mark.gl
def test_the_brdf_table_equals_a_quadrature_over_the_hemisphere(table):
    # At texel centres of roughness 0.25-1 (the lobe 0.06 rad wide or more: resolved by the
    # 3000 x 720 grid: a 6000 x 1440 one gives the same to 1e-4) and n.v 0.1-1: the table's
    # 16384 Hammersley samples within 0.002 of the quadrature (measured 0.001 at the worst
    # point, n.v 0.1 and roughness 0.25; the median 3e-5; with Karis' 1024 samples 0.011).
    size = table.shape[0]
    worst = 0.0
    for i in (12, 38, 64, 100, 127):
        for j in (32, 64, 96, 127):
            nov, rough = (i + 0.5) / size, (j + 0.5) / size
            want = table_by_quadrature(nov, rough)
            err = np.max(np.abs(table[j, i] - want))
            worst = max(worst, err)
    print(f"table vs quadrature: {worst:.2e}")
    assert worst < 0.002


@pytest.mark.gl
def test_the_brdf_table_against_published_values(table):
    size = table.shape[0]
    nov = (np.arange(size) + 0.5) / size
    # The mirror (roughness -> 0: G -> 1, h = n): scale = 1 - (1 - n.v)^5, bias = (1 - n.v)^5
    # (Schlick 1994's Fresnel), so scale + bias = 1; at n.v = 1 the bias is 0. The first row
    # is roughness 1/256 (alpha 1.5e-5): within 0.005.
    assert np.allclose(table[0, :, 0], 1 - (1 - nov) ** 5, atol=0.005)
    assert np.allclose(table[0, :, 1], (1 - nov) ** 5, atol=0.005)
    assert table[0, -1].sum() == pytest.approx(1.0, abs=0.002)
    # Roughness 1, n.v = 1: alpha = 1, D = 1/pi, G = 2 mu / (1 + mu) at mu = n.l, and v.h >=
    # cos 45 deg makes Fc < 0.0022: scale = 1/2 int 2 mu / (1 + mu) dmu = 1 - ln 2 (0.307)
    # less Fc's share (< 3e-4). The corner texel is at 0.996 on both axes: extrapolated
    # linearly from the last two texels of each axis to 1 (the scale is smooth there: an
    # error of order (1/128)^2), within 0.001 (measured 6e-5).
    t = table[..., 0].astype(np.float64)

    def at_nov_1(j):
        return t[j, -1] + 0.5 * (t[j, -1] - t[j, -2])

    corner = at_nov_1(-1) + 0.5 * (at_nov_1(-1) - at_nov_1(-2))
    assert corner == pytest.approx(1 - math.log(2), abs=0.001)


def test_the_dds_file_reads_back_by_the_layout_spec(tmp_path):
    from skydome.io.dds import write_dds_cube

    rng = np.random.default_rng(1)
    levels = [rng.uniform(0, 5e4, (6, m, m, 3)) for m in (16, 8, 4)]
    path = write_dds_cube(tmp_path / "env.dds", levels, scale=0.5)
    dds = read_dds_cube(path.read_bytes())
    assert dds["size"] == 124 and dds["pf_size"] == 32 and dds["fourcc"] == b"DX10"
    assert dds["width"] == dds["height"] == 16 and dds["mips"] == 3 and dds["pitch"] == 16 * 8
    assert dds["flags"] & 0x20000 and dds["pf_flags"] == 0x4  # MIPMAPCOUNT; FOURCC
    assert dds["caps"] == 0x401008 and dds["caps2"] == 0xFE00  # complex, texture, mipmap
    assert (dds["dxgi"], dds["dimension"], dds["misc"], dds["array_size"]) == (10, 3, 4, 1)
    assert dds["end"] == dds["length"]  # nothing before or after the 6 x 3 images
    for f in range(6):
        for k, level in enumerate(levels):
            got = dds["faces"][f][k].astype(np.float64)
            # half floats: 11 significant bits, a relative error up to 2^-11
            assert np.allclose(got[..., :3], 0.5 * level[f], rtol=2.0**-11, atol=1e-3)
            assert np.all(got[..., 3] == 1.0)


def read_ktx2_cube(blob: bytes) -> dict:
    """A KTX2 reader written from the Khronos KTX 2.0 specification (sections 3.1-3.10): the
    identifier, the header, the level index, the basic data format descriptor's fields."""
    assert blob[:12] == bytes([0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A,
                               0x0A])  # fmt: skip
    (vk_format, type_size, width, height, depth, layers, faces, levels, scheme) = (
        struct.unpack_from("<9I", blob, 12)
    )
    dfd_offset, dfd_length, kvd_offset, kvd_length = struct.unpack_from("<4I", blob, 48)
    sgd_offset, sgd_length = struct.unpack_from("<2Q", blob, 64)
    index = [struct.unpack_from("<3Q", blob, 80 + 24 * k) for k in range(levels)]
    total, vendor_type, version, block_size = struct.unpack_from("<IIHH", blob, dfd_offset)
    model, primaries, transfer, flags = struct.unpack_from("<4B", blob, dfd_offset + 12)
    bytes_plane0 = blob[dfd_offset + 20]
    samples = [struct.unpack_from("<HBB4xII", blob, dfd_offset + 28 + 16 * i)
               for i in range((block_size - 24) // 16)]  # fmt: skip
    data = []
    for k, (offset, length, uncompressed) in enumerate(index):
        m = max(width >> k, 1)
        assert length == uncompressed == 6 * m * m * 8 and offset % 8 == 0
        data.append(np.frombuffer(blob, "<f2", 6 * m * m * 4, offset).reshape(6, m, m, 4))
    return {
        "vk_format": vk_format, "type_size": type_size, "width": width, "height": height,
        "depth": depth, "layers": layers, "faces": faces, "levels": levels, "scheme": scheme,
        "dfd": (dfd_length == total, vendor_type, version, block_size, model, primaries,
                transfer, flags, bytes_plane0),
        "kvd": (kvd_offset, kvd_length), "sgd": (sgd_offset, sgd_length),
        "samples": samples, "offsets": [i[0] for i in index], "data": data,
    }  # fmt: skip


def test_the_ktx2_file_reads_back_by_the_spec(tmp_path):
    from skydome.io.ktx2 import write_ktx2_cube

    rng = np.random.default_rng(2)
    levels = [rng.uniform(0, 5e4, (6, m, m, 3)) for m in (16, 8, 4)]
    path = write_ktx2_cube(tmp_path / "env.ktx2", levels)
    k = read_ktx2_cube(path.read_bytes())
    # VK_FORMAT_R16G16B16A16_SFLOAT (97), 2-byte components, a cube (6 faces, no layers)
    assert (k["vk_format"], k["type_size"], k["faces"], k["layers"], k["depth"]) == (97, 2, 6, 0, 0)
    assert (k["width"], k["height"], k["levels"], k["scheme"]) == (16, 16, 3, 0)
    # DFD: Khronos basic block v2 of 24 + 4 x 16 bytes, RGBSDA, BT.709, linear, 8 bytes/texel
    assert k["dfd"] == (True, 0, 2, 88, 1, 1, 1, 0, 8)
    # R, G, B, A: 16 bits each at 0, 16, 32, 48, signed float (0xC0), range -1.0..1.0
    assert k["samples"] == [(16 * i, 15, c | 0xC0, 0xBF800000, 0x3F800000)
                            for i, c in enumerate((0, 1, 2, 15))]  # fmt: skip
    assert k["kvd"] == (0, 0) and k["sgd"] == (0, 0)
    assert k["offsets"][2] < k["offsets"][1] < k["offsets"][0]  # smallest level first
    assert k["offsets"][0] + 6 * 16 * 16 * 8 == path.stat().st_size
    for level, got in zip(levels, k["data"], strict=True):
        assert np.allclose(got[..., :3].astype(np.float64), level, rtol=2.0**-11, atol=1e-3)
        assert np.all(got[..., 3] == 1.0)


@pytest.mark.gl
def test_cli_writes_the_cube_and_the_table(tmp_path):
    import OpenEXR

    dds, ktx2, table = tmp_path / "x.dds", tmp_path / "x.ktx2", tmp_path / "b.exr"
    r = run_cli("lighting", "--sun-elevation", "30", "--sun-azimuth", "180",
                "-o", str(dds), "-o", str(ktx2), "--brdf-table", str(table))  # fmt: skip
    assert r.returncode == 0, r.stderr
    cube = read_dds_cube(dds.read_bytes())
    assert cube["width"] == 128 and cube["mips"] == 6
    same = read_ktx2_cube(ktx2.read_bytes())["data"]  # the same texels in both files
    assert all(np.array_equal(same[k][f], cube["faces"][f][k]) for k in range(6) for f in range(6))
    faces = [np.asarray(cube["faces"][f][0][..., :3], np.float64) for f in range(6)]
    # The Sun at azimuth 180 lights the south (-Z) face's sky more than the north (+Z) one's;
    # the up face (+Y) is sky, the down face (-Y) the ground, darker.
    assert faces[5][:64].mean() > faces[4][:64].mean()
    assert faces[2].mean() > faces[3].mean()
    with OpenEXR.File(str(table), separate_channels=True) as f:
        ch = f.channels()
        scale, bias = np.asarray(ch["R"].pixels), np.asarray(ch["G"].pixels)
        assert "Schlick-GGX" in f.header()["skydome_table"]
    # a reflectance: scale + bias within [0, 1] (the estimator's 1e-4 above 1 allowed)
    assert scale.shape == (128, 128) and scale.min() >= 0.0 and (scale + bias).max() < 1.001
    assert bias[0, 0] > 0.9 and bias[0, -1] < 1e-3  # grazing mirror: ~1; facing: 0
    for args, words in (
        (("--cube-size", "100"), "--cube-size 100"),
        (("--cube-size", "4"), "--cube-size 4"),
        (("--cube-scale", "0"), "--cube-scale"),
        (("--brdf-table", str(tmp_path / "b.png")), "b.png"),
        (("--cube-scale", "1e6"), "65504"),
    ):
        out = tmp_path / "bad.dds"
        r = run_cli("lighting", "--sun-elevation", "30", "--size", "64x32", "-o", str(out), *args)
        assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1, r.stderr
        assert words in r.stderr, r.stderr
        assert not out.exists() and not (tmp_path / "b.png").exists()
