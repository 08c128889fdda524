"""GL layer: context, shader library (#include, #define, error locations), passes."""

import numpy as np
import pytest

from skydome.errors import GLError
from skydome.gpu import FullscreenPass, expand, gl_info


def test_context_reports_renderer(ctx):
    info = gl_info(ctx)
    assert info.version_code >= 330
    assert info.renderer and info.version
    # This CI machine has no GPU: Mesa's llvmpipe is a software rasterizer.
    if "llvmpipe" in info.renderer:
        assert info.software


def test_include_and_defines_expand():
    src = expand(
        "probe.glsl",
        {"ANSWER": 42, "SCALE": 0.5, "FLAG": True},
        source='#include "common/constants.glsl"\n#include "common/constants.glsl"\nvoid main() {}\n',
    )
    assert src.text.startswith("#version 330 core\n")
    assert "#define ANSWER 42" in src.text and "#define SCALE 0.5" in src.text
    assert "#define FLAG 1" in src.text
    assert src.text.count("const float PI") == 1  # each file included once
    assert src.files == ("<defines>", "probe.glsl", "common/constants.glsl")


def test_compile_error_names_file_and_line(ctx):
    source = '#include "common/constants.glsl"\nout vec4 c;\n\nvoid main() { c = vec4(PI, undefined_name, 0, 1); }\n'
    with pytest.raises(GLError, match=r"probe\.glsl:4"):
        FullscreenPass(ctx, "probe.glsl", inputs=(), source=source)


def test_error_in_included_file_names_that_file(ctx):
    with pytest.raises(GLError, match=r"transmittance_lut\.glsl:\d+"):
        # NUM_GROUPS is not needed, but the table code needs nothing undefined; break it by
        # defining one of its names as a macro that makes its declaration invalid.
        FullscreenPass(
            ctx,
            "probe.glsl",
            {"u_transmittance_size": "1.0"},
            inputs=(),
            source='#include "atmosphere/transmittance_lut.glsl"\nout vec4 c;\nvoid main() { c = vec4(0); }\n',
        )


def test_missing_shader_file():
    with pytest.raises(GLError, match="not found"):
        expand("no_such_file.glsl")


def test_fullscreen_pass_writes_every_pixel(ctx):
    p = FullscreenPass(
        ctx,
        "probe.glsl",
        inputs=(),
        source="out vec4 c;\nvoid main() { c = vec4(gl_FragCoord.xy, 1.0, 1.0); }\n",
    )
    tex = ctx.texture((37, 23), 4, dtype="f4")
    fbo = ctx.framebuffer(color_attachments=[tex])
    fbo.clear(-1.0, -1.0, -1.0, -1.0)
    p.draw(fbo)
    data = np.frombuffer(fbo.read(components=4, dtype="f4"), dtype=np.float32).reshape(23, 37, 4)
    assert np.all(data[..., 2] == 1.0)
    np.testing.assert_array_equal(data[0, :, 0], np.arange(37) + 0.5)  # pixel centres


def test_no_context_raises_install_hint(monkeypatch):
    import moderngl

    from skydome.gpu import create_context

    def fail(**kwargs):
        raise Exception("eglGetDisplay failed")

    monkeypatch.setattr(moderngl, "create_context", fail)
    with pytest.raises(GLError, match="libegl1 libgl1-mesa-dri"):
        create_context()
