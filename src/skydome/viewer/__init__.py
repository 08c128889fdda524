"""The interactive viewer (``skydome view``) and the notebook widget.

- ``controls``: the view's state (camera, time, display) and the input that moves it (no GL);
- ``scene``: the Sky a viewer shows for that state (times, places, exposure, swaps);
- ``rebuild``: new atmosphere tables computed in a background process;
- ``frame_timer``: CPU and GPU time per frame and per pass;
- ``screenshot``: PNG and EXR of what is on screen;
- ``imgui_gl``, ``panel``: the Dear ImGui control panel (``imgui-bundle``), drawn with moderngl;
- ``app``: the glfw window and its main loop;
- ``widget``: the Jupyter widget (``jupyter_rfb``).

glfw, imgui-bundle and jupyter-rfb are optional (``pip install 'skydome[viewer]'``): only
``app``, ``panel``, ``imgui_gl`` and ``widget`` import them, on first use.
"""

from __future__ import annotations

#: What to install for the window and the widget.
INSTALL_HINT = "pip install 'skydome[viewer]' (glfw, imgui-bundle, jupyter-rfb)"


def require(module: str, package: str):
    """Import ``module`` or raise ParameterError saying how to install ``package``."""
    import importlib

    from skydome.errors import ParameterError

    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise ParameterError(
            f"the viewer needs {package} ({exc}); install it with {INSTALL_HINT}"
        ) from None
