"""The GL state the precomputation leaves behind: no error flag for the next user of the
context (the viewer turns any flag into a GLError and stops)."""

from __future__ import annotations

from tests.conftest import TINY_TABLES


def test_a_precompute_leaves_no_gl_error(ctx):
    """After a precomputation, making and drawing into a new framebuffer (what the frame
    graph does next) raises no GL error: the precomputation's last framebuffer, released,
    is no longer the bound one (moderngl rebinds its bound framebuffer after making one,
    and binding a deleted name is GL_INVALID_OPERATION; OpenGL 4.6 core, section 9.2)."""
    from skydome.atmosphere import preset
    from skydome.atmosphere.precompute import precompute

    ctx.error  # noqa: B018  (a flag left by an earlier test is not this one's)
    tables = precompute(ctx, preset("earth"), TINY_TABLES)
    try:
        assert ctx.error == "GL_NO_ERROR"
        tex = ctx.texture((4, 4), 4, dtype="f4")
        fbo = ctx.framebuffer(color_attachments=[tex])
        assert ctx.error == "GL_NO_ERROR"
        fbo.clear(0.25, 0.5, 0.75, 1.0)
        assert ctx.error == "GL_NO_ERROR"
        fbo.release()
        tex.release()
    finally:
        tables.release()


def test_releasing_the_bound_framebuffer_unbinds_it(ctx):
    """``release_unbound`` on the bound framebuffer binds the default one; a plain release
    leaves the deleted name bound and the next framebuffer made flags the error (the
    defect the precomputation had)."""
    from skydome.gpu.textures import release_unbound

    def error_after(release) -> str:
        ctx.detect_framebuffer(0).use()  # a valid binding to start from
        ctx.error  # noqa: B018
        tex = ctx.texture((4, 4), 4)
        fbo = ctx.framebuffer(color_attachments=[tex])
        fbo.use()
        release(fbo)
        tex.release()
        tex2 = ctx.texture((4, 4), 4)
        fbo2 = ctx.framebuffer(color_attachments=[tex2])
        error = ctx.error
        ctx.detect_framebuffer(0).use()
        fbo2.release()
        tex2.release()
        ctx.error  # noqa: B018
        return error

    assert error_after(lambda fbo: fbo.release()) == "GL_INVALID_OPERATION"  # the defect
    assert error_after(release_unbound) == "GL_NO_ERROR"
