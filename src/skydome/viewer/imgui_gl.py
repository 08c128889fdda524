"""Dear ImGui (``imgui-bundle``) on moderngl: the draw lists rendered, its textures kept,
and glfw's input handed to it. No PyOpenGL: every GL call goes through moderngl.

The renderer honours ImGui 1.92's ``RendererHasTextures`` protocol (the font atlas and
other textures are created, updated and destroyed as ImGui asks); the platform half feeds
``io`` the display size, the framebuffer scale (HiDPI), the time step, the pointer, the
wheel, keys and text.
"""

from __future__ import annotations

import ctypes

import numpy as np

_VERTEX_SHADER = """
#version 330
uniform mat4 u_projection;
in vec2 in_position;
in vec2 in_uv;
in vec4 in_colour;
out vec2 v_uv;
out vec4 v_colour;
void main() {
    v_uv = in_uv;
    v_colour = in_colour;
    gl_Position = u_projection * vec4(in_position, 0.0, 1.0);
}
"""

_FRAGMENT_SHADER = """
#version 330
uniform sampler2D u_texture;
in vec2 v_uv;
in vec4 v_colour;
out vec4 frag;
void main() { frag = v_colour * texture(u_texture, v_uv); }
"""


class ImguiRenderer:
    """Renders ImGui's draw data into the current framebuffer with moderngl."""

    def __init__(self, ctx):
        from imgui_bundle import imgui

        self.imgui = imgui
        self.ctx = ctx
        self.program = ctx.program(vertex_shader=_VERTEX_SHADER, fragment_shader=_FRAGMENT_SHADER)
        self.program["u_texture"].value = 0
        self._vbo = ctx.buffer(reserve=1 << 16, dynamic=True)
        self._ibo = ctx.buffer(reserve=1 << 16, dynamic=True)
        self._vao = None
        self._make_vao()
        self.textures: dict[int, object] = {}
        self._next_id = 1
        io = imgui.get_io()
        io.backend_flags |= imgui.BackendFlags_.renderer_has_textures
        limit = int(ctx.info.get("GL_MAX_TEXTURE_SIZE", 8192))
        platform = imgui.get_platform_io()
        platform.renderer_texture_max_width = limit
        platform.renderer_texture_max_height = limit

    def _make_vao(self) -> None:
        if self._vao is not None:
            self._vao.release()
        self._vao = self.ctx.vertex_array(
            self.program,
            [(self._vbo, "2f 2f 4f1", "in_position", "in_uv", "in_colour")],
            index_buffer=self._ibo,
            index_element_size=self.imgui.INDEX_SIZE,
        )

    # ------------------------------------------------------------------ textures

    def update_textures(self) -> None:
        """Create, update and destroy the textures ImGui asks for."""
        imgui = self.imgui
        status = imgui.ImTextureStatus
        for tex in imgui.get_platform_io().textures:
            if tex.status == status.want_create or tex.status == status.want_updates:
                pixels = np.ascontiguousarray(tex.get_pixels_array())
                tid = int(tex.tex_id)
                gl_tex = self.textures.get(tid)
                if gl_tex is None or gl_tex.size != (tex.width, tex.height):
                    if gl_tex is not None:
                        gl_tex.release()
                    gl_tex = self.ctx.texture((tex.width, tex.height), 4, pixels.tobytes())
                    gl_tex.filter = (self.ctx.LINEAR, self.ctx.LINEAR)
                    gl_tex.repeat_x = gl_tex.repeat_y = False
                    if tid == 0:
                        tid = self._next_id
                        self._next_id += 1
                        tex.set_tex_id(tid)
                    self.textures[tid] = gl_tex
                else:  # the whole atlas again: updates are rare (a new glyph size)
                    gl_tex.write(pixels.tobytes())
                tex.status = status.ok
            elif tex.status == status.want_destroy:
                gl_tex = self.textures.pop(int(tex.tex_id), None)
                if gl_tex is not None:
                    gl_tex.release()
                tex.set_tex_id(0)
                tex.status = status.destroyed

    # ------------------------------------------------------------------ drawing

    def render(self, draw_data, framebuffer_size: tuple[int, int]) -> None:
        """Draw ``draw_data`` (``imgui.get_draw_data()``) over the current framebuffer of
        ``framebuffer_size`` pixels."""
        imgui, ctx = self.imgui, self.ctx
        self.update_textures()
        fb_w, fb_h = framebuffer_size
        if fb_w <= 0 or fb_h <= 0 or draw_data is None:
            return
        x0, y0 = draw_data.display_pos.x, draw_data.display_pos.y
        dw, dh = draw_data.display_size.x, draw_data.display_size.y
        if dw <= 0 or dh <= 0:
            return
        sx, sy = fb_w / dw, fb_h / dh  # framebuffer pixels per ImGui unit (HiDPI)
        projection = np.array(
            [
                [2.0 / dw, 0.0, 0.0, 0.0],
                [0.0, -2.0 / dh, 0.0, 0.0],
                [0.0, 0.0, -1.0, 0.0],
                [-(2 * x0 + dw) / dw, (2 * y0 + dh) / dh, 0.0, 1.0],
            ],
            dtype="f4",
        )
        self.program["u_projection"].write(projection.tobytes())
        ctx.viewport = (0, 0, fb_w, fb_h)
        ctx.enable_only(ctx.BLEND)
        ctx.blend_func = ctx.SRC_ALPHA, ctx.ONE_MINUS_SRC_ALPHA
        try:
            for commands in draw_data.cmd_lists:
                vtx = commands.vtx_buffer.size() * imgui.VERTEX_SIZE
                idx = commands.idx_buffer.size() * imgui.INDEX_SIZE
                if vtx == 0 or idx == 0:
                    continue
                grown = False
                if vtx > self._vbo.size:
                    self._vbo.orphan(_grow(vtx))
                    grown = True
                if idx > self._ibo.size:
                    self._ibo.orphan(_grow(idx))
                    grown = True
                if grown:
                    self._make_vao()
                self._vbo.write(ctypes.string_at(commands.vtx_buffer.data_address(), vtx))
                self._ibo.write(ctypes.string_at(commands.idx_buffer.data_address(), idx))
                for cmd in commands.cmd_buffer:
                    cx0, cy0, cx1, cy1 = cmd.clip_rect
                    left, top = (cx0 - x0) * sx, (cy0 - y0) * sy
                    right, bottom = (cx1 - x0) * sx, (cy1 - y0) * sy
                    if right <= left or bottom <= top:
                        continue
                    tex = self.textures.get(int(cmd.tex_ref.get_tex_id()))
                    if tex is None:
                        continue
                    tex.use(0)
                    ctx.scissor = (
                        int(left),
                        int(fb_h - bottom),
                        int(right - left),
                        int(bottom - top),
                    )
                    self._vao.render(
                        ctx.TRIANGLES, vertices=int(cmd.elem_count), first=int(cmd.idx_offset)
                    )
        finally:
            ctx.scissor = None
            ctx.disable(ctx.BLEND)
            ctx.blend_func = ctx.ONE, ctx.ZERO

    def release(self) -> None:
        """Free the program, buffers and textures (ImGui's textures are marked destroyed)."""
        for tex in self.textures.values():
            tex.release()
        self.textures.clear()
        for tex in self.imgui.get_platform_io().textures:
            tex.set_tex_id(0)
            tex.status = self.imgui.ImTextureStatus.destroyed
        for obj in (self._vao, self._vbo, self._ibo, self.program):
            obj.release()


def _grow(n: int) -> int:
    """A buffer size (bytes) of at least ``n``: the next power of two."""
    return 1 << max(16, (int(n) - 1).bit_length())


#: glfw key names -> ImGui key names (both libraries' names, lower case).
_NAMED_KEYS = {
    "TAB": "tab", "LEFT": "left_arrow", "RIGHT": "right_arrow", "UP": "up_arrow",
    "DOWN": "down_arrow", "PAGE_UP": "page_up", "PAGE_DOWN": "page_down", "HOME": "home",
    "END": "end", "INSERT": "insert", "DELETE": "delete", "BACKSPACE": "backspace",
    "SPACE": "space", "ENTER": "enter", "ESCAPE": "escape", "KP_ENTER": "keypad_enter",
    "LEFT_CONTROL": "left_ctrl", "RIGHT_CONTROL": "right_ctrl", "LEFT_SHIFT": "left_shift",
    "RIGHT_SHIFT": "right_shift", "LEFT_ALT": "left_alt", "RIGHT_ALT": "right_alt",
    "LEFT_SUPER": "left_super", "RIGHT_SUPER": "right_super", "MINUS": "minus",
    "PERIOD": "period", "COMMA": "comma", "EQUAL": "equal",
}  # fmt: skip
_MODIFIERS = {
    "left_ctrl": "mod_ctrl", "right_ctrl": "mod_ctrl", "left_shift": "mod_shift",
    "right_shift": "mod_shift", "left_alt": "mod_alt", "right_alt": "mod_alt",
    "left_super": "mod_super", "right_super": "mod_super",
}  # fmt: skip


def key_map(glfw, imgui) -> dict[int, object]:
    """glfw key codes -> ``imgui.Key`` members (named keys, letters and digits)."""
    out = {}
    for g, i in _NAMED_KEYS.items():
        out[getattr(glfw, f"KEY_{g}")] = getattr(imgui.Key, i)
    for c in "ABCDEFGHIJKLMNOPQRSTUVWXYZ":
        out[getattr(glfw, f"KEY_{c}")] = getattr(imgui.Key, c.lower())
    for d in "0123456789":
        out[getattr(glfw, f"KEY_{d}")] = getattr(imgui.Key, f"_{d}")
    return out


class ImguiPlatform:
    """Feeds ImGui's io from a glfw window's events (call the ``on_*`` methods from the
    window's callbacks, and :meth:`new_frame` before ``imgui.new_frame()``)."""

    def __init__(self, glfw, window):
        from imgui_bundle import imgui

        self.imgui, self.glfw, self.window = imgui, glfw, window
        self.io = imgui.get_io()
        self.keys = key_map(glfw, imgui)

    def new_frame(self, dt_s: float) -> None:
        """Set the display size (window units), the framebuffer scale and the time step."""
        imgui, glfw = self.imgui, self.glfw
        w, h = glfw.get_window_size(self.window)
        fw, fh = glfw.get_framebuffer_size(self.window)
        self.io.display_size = imgui.ImVec2(float(w), float(h))
        if w > 0 and h > 0:
            self.io.display_framebuffer_scale = imgui.ImVec2(fw / w, fh / h)
        self.io.delta_time = max(float(dt_s), 1e-4)

    def on_key(self, key: int, action: int) -> None:
        k = self.keys.get(key)
        if k is None:
            return
        down = action != self.glfw.RELEASE
        self.io.add_key_event(k, down)
        name = _MODIFIERS.get(k.name)
        if name is not None:
            self.io.add_key_event(getattr(self.imgui.Key, name), down)

    def on_char(self, codepoint: int) -> None:
        if 0 < codepoint < 0x110000:
            self.io.add_input_character(int(codepoint))

    def on_cursor(self, x: float, y: float) -> None:
        self.io.add_mouse_pos_event(float(x), float(y))

    def on_mouse_button(self, button: int, action: int) -> None:
        if 0 <= button < 5:
            self.io.add_mouse_button_event(int(button), action == self.glfw.PRESS)

    def on_scroll(self, dx: float, dy: float) -> None:
        self.io.add_mouse_wheel_event(float(dx), float(dy))
