"""Shared fixtures: one headless GL context and cached renderers for the whole session; the
tiers of the suite (markers given here, by rule and by list: see pytest_collection_modifyitems).

``make test`` runs every test; ``make test-fast`` leaves out the ``slow``, ``window`` and
``soak`` tiers. ``SKYDOME_CHECK_TIERS=1 python -m pytest [-m ...]`` reports where the lists
below no longer tell the truth: a test that drew with OpenGL in this process without the
``gl`` marker, one that took more than SLOW_S seconds (less the session's atmosphere tables it
built) without ``slow``, a name in SLOW_TESTS that no collected test has.
"""

from __future__ import annotations

import atexit
import os
import shutil
import tempfile
import time
from pathlib import Path

import pytest

_TEST_CACHE_PREFIX = "skydome-test-cache-"


def _remove_orphan_test_caches() -> None:
    """Remove the test caches of sessions that are gone: each holds ~1 GB of tables, and a
    session killed before its exit handler ran would otherwise leave its own behind for good
    (a CI machine that fills its disk that way fails every later run)."""
    for folder in Path(tempfile.gettempdir()).glob(_TEST_CACHE_PREFIX + "*"):
        pid_text = folder.name[len(_TEST_CACHE_PREFIX) :].split("-", 1)[0]
        if pid_text.isdigit():
            try:
                os.kill(int(pid_text), 0)
                continue  # its session still runs
            except ProcessLookupError:
                pass
            except PermissionError:
                continue  # another user's live process
        elif time.time() - folder.stat().st_mtime < 6 * 3600:
            continue  # an old-style name: only when it cannot belong to a running session
        shutil.rmtree(folder, ignore_errors=True)


# Tests never touch the user's cache: one fresh cache directory per test session, named by
# this process's id, removed when the session ends.
_remove_orphan_test_caches()
_TEST_CACHE = tempfile.mkdtemp(prefix=f"{_TEST_CACHE_PREFIX}{os.getpid()}-")
os.environ["SKYDOME_CACHE"] = _TEST_CACHE
atexit.register(shutil.rmtree, _TEST_CACHE, ignore_errors=True)

from skydome.gpu import shared_context  # noqa: E402 - after SKYDOME_CACHE is set


def _tiny_tables():
    from skydome.atmosphere.precompute_config import PrecomputeConfig

    return PrecomputeConfig(
        wavelengths="fast",
        orders=2,
        scattering_size=(8, 32, 8, 4),
        ms_size=(8, 16, 8, 4),
        irradiance_size=(16, 8),
        transmittance_size=(64, 16),
    )


#: Tables small enough to precompute in a fraction of a second (cache and plumbing tests).
TINY_TABLES = _tiny_tables()


@pytest.fixture(scope="session")
def ctx():
    return shared_context()


@pytest.fixture(scope="session")
def renderer_factory():
    from tests.air_frames import single_frames

    return single_frames


# ---------------------------------------------------------------------------- the tiers

#: Modules whose tests draw with OpenGL (in this process or in a `skydome` child process)
#: without asking for the ``ctx`` fixture: every test in them is marked ``gl``, the few that
#: do not draw too (a new test there is covered without a list to update).
GL_MODULES = frozenset({
    "astro/test_astro_events_cli.py", "test_cache.py", "test_cli.py", "test_cli_clouds.py",
    "test_cli_knobs.py", "test_cli_night.py", "test_cli_scene.py", "test_clouds.py",
    "test_default_path_vs_mc.py", "test_density_profiles.py", "test_display.py",
    "test_docs.py", "test_frame_graph.py", "test_frames_vs_mc.py", "test_lifetimes.py",
    "test_light_pollution.py", "test_mars.py", "test_milky_way.py", "test_night_sky.py",
    "test_planets_layer.py", "test_point_sources.py", "test_precompute.py",
    "test_precomputed_render.py", "test_readme_snippets.py", "test_real_earth.py",
    "test_scene.py", "test_single_scattering.py", "test_sky_glow.py", "test_sky_view.py",
    "test_smooth_layers.py", "test_stars.py", "test_sun_moon_disks.py",
    "test_viewer_widget.py",
})  # fmt: skip
#: Fixtures that give a test OpenGL: the headless context, the cached air renderers.
GL_FIXTURES = frozenset({"ctx", "renderer_factory"})
#: The fixture of the tests that open a window (glfw under Xvfb): marked ``window`` and ``gl``.
WINDOW_FIXTURES = frozenset({"x_display"})

#: Seconds above which a test is ``slow`` (on 2 CPU cores with Mesa llvmpipe).
SLOW_S = 3.0
#: The slow tests, by module: a test's name (all its parameters) or name[parameters].
#: Measured with ``--durations=0`` (setup, call and teardown) on 2 cores shared with other jobs
#: (load 1-5), in the whole suite and in the fast tier. Atmosphere tables are built once per
#: session (cached on disk), by the first test that needs them: the default set
#: (``PrecomputeConfig()``, ~5 s here), which most GL tests use, is paid by whichever fast
#: test comes first, and is not held against it (SKYDOME_CHECK_TIERS counts a test's time
#: less the tables it built); the first fast test to need a set that no other fast test needs
#: (mars, hazy, more orders, the command line's own) is listed, so that make test-fast does
#: not build them.
SLOW_TESTS: dict[str, tuple[str, ...]] = {
    "astro/test_astro_events_cli.py": (
        "test_cli_ephemeris_ground_illuminance",
        "test_cli_events_polar_day_and_night",
        "test_ground_illuminance_matches_the_renderer[earth-60.0-0.0-0.002]",
        "test_ground_illuminance_matches_the_renderer[hazy-5.0-0.0-0.01]",
    ),
    "astro/test_planet_deflection.py": ("test_deflection_adds_no_error_near_conjunction",),
    "test_solar_eclipse.py": ("test_direct_sunlight_factor_through_the_partial_phase_vs_de421",),
    "astro/test_stars.py": ("test_packaged_files_are_what_the_tool_builds",),
    "test_aerosols.py": ("test_higher_asymmetry_type_has_brighter_aureole",),
    "test_atmosphere_knobs.py": ("test_more_aerosol_dims_the_sun_and_whitens_the_sky",),
    "test_batch.py": (
        "test_a_local_cluster_of_two_workers_renders_40_jobs_as_one_process_does",
        "test_a_worker_killed_mid_run_leaves_every_output_once_and_whole",
        "test_a_runner_keeps_its_memory_flat_over_many_jobs",
        "test_outputs_are_the_single_renders_and_the_manifest_their_light",
    ),
    "test_cache.py": (
        "test_cli_warns_in_one_line_and_rebuilds",
        "test_damaged_header_through_the_sky",
        "test_every_header_byte_is_checked",
        "test_what_is_not_a_cache_file_is_replaced",
    ),
    "test_cli.py": (
        "test_cache_warning_is_one_line",
        "test_equirect_and_cubemap_sizes",
        "test_hdr_and_jpg_outputs",
        "test_render_png_and_exr",
    ),
    "test_cli_clouds.py": (
        "test_render_with_clouds_writes_a_cloudy_frame",
        "test_timelapse_moves_the_clouds_with_the_wind",
    ),
    "test_cli_knobs.py": (
        "test_precompute_knobs_key_the_tables",
        "test_render_knobs_act_on_the_frame",
    ),
    "test_cli_scene.py": ("test_timelapse_killed_leaves_a_temporary_file_the_next_run_removes",),
    "test_cli_view.py": ("test_the_viewer_draws_clouds_interactively",),
    "test_crepuscular_rays.py": ("test_crepuscular_rays_converge_on_the_sun",),
    "test_crystal_optics.py": ("test_tracer_on_a_sphere_is_the_drops_geometric_optics",),
    "test_fogbow.py": ("test_the_fogbow_follows_the_droplets_size",),
    "test_cloud_noise.py": ("test_default_textures_and_caches",),
    "test_cloud_phase.py": (
        "test_asymmetry_of_water_clouds",
        "test_tool_rebuilds_the_packaged_table",
    ),
    "test_clouds.py": (
        "test_another_seed_gives_other_clouds",
        "test_cloudy_frame_is_finite_deterministic_and_cloudy",
        "test_covered_fraction_grows_with_coverage",
        "test_interactive_mode_converges_to_the_full_quality_frame",
        "test_shadows_on_the_ground_move_with_the_wind",
    ),
    "test_clouds_mc.py": ("test_renderer_table_worst_case_error",),
    "test_default_path_vs_mc.py": (
        "test_default_tables_match_monte_carlo_luminance",
        "test_interpolated_orders_match_computing_all_16",
    ),
    "test_density_profiles.py": ("test_tabulated_exponentials_reproduce_the_exponential_frame",),
    "test_docs.py": (
        "test_example_runs_and_writes_sane_files[atmospheres.py]",
        "test_example_runs_and_writes_sane_files[batch.sh]",
        "test_example_runs_and_writes_sane_files[blender_cli.sh]",
        "test_example_runs_and_writes_sane_files[blender_hdri.py]",
        "test_example_runs_and_writes_sane_files[clouds.py]",
        "test_example_runs_and_writes_sane_files[eye_adaptation.py]",
        "test_example_runs_and_writes_sane_files[lighting.py]",
        "test_example_runs_and_writes_sane_files[night_sky.py]",
        "test_example_runs_and_writes_sane_files[place_and_time.py]",
        "test_example_runs_and_writes_sane_files[timelapse.sh]",
        "test_example_runs_and_writes_sane_files[tour.py]",
        "test_example_runs_and_writes_sane_files[tour_cli.sh]",
        "test_site_builds_strict",
        "test_the_example_notebook_runs_and_shows_its_outputs",
    ),
    "test_frames_vs_mc.py": (
        "test_frames_match_monte_carlo",
        "test_ground_shading_matches_monte_carlo",
    ),
    "test_lifetimes.py": (
        "test_200_skies_made_rendered_and_dropped_leak_nothing",
        "test_skies_share_tables_and_the_last_holder_frees_them",
    ),
    "test_lighting_ibl.py": (
        "test_the_brdf_table_equals_a_quadrature_over_the_hemisphere",
        "test_cli_writes_the_cube_and_the_table",
    ),
    "test_mars.py": (
        "test_blue_around_the_setting_sun_butterscotch_elsewhere",
        "test_daytime_sky_is_butterscotch",
    ),
    "test_ms_reference.py": (
        "test_double_scattering_quadrature_is_converged",
        "test_guiding_does_not_bias",
        "test_mc_double_scattering_matches_quadrature",
        "test_spectral_mis_matches_single_wavelength_runs",
    ),
    "test_halos.py": (
        "test_no_circumzenithal_arc_with_the_sun_above_32_degrees",
        "test_sky_draws_the_22_degree_halo",
        "test_sky_draws_sun_dogs_beside_the_sun",
        "test_frames_without_cirrus_do_not_depend_on_the_halos",
        "test_diamond_dust_draws_the_22_degree_halo_near_the_ground",
    ),
    "test_point_sources.py": (
        "test_equirect_flux_is_the_illuminance_at_any_resolution[4096]",
        "test_pixel_weights_are_the_gaussian_integrals[0.8-180.02-4096]",
        "test_seeing_adds_in_quadrature",
    ),
    "test_precompute.py": (
        "test_energy_conservation",
        "test_finite_and_non_negative_everywhere",
        "test_matches_monte_carlo_reference",
        "test_orders_increase_monotonically_and_converge",
        "test_single_order_matches_single_scattering_renderer[0.0-earth]",
        "test_single_order_matches_single_scattering_renderer[0.0-earth_bruneton]",
        "test_sky_irradiance_against_monte_carlo",
        "test_twilight_is_blue_and_darkens",
    ),
    "test_precomputed_render.py": (
        "test_cache_rebuild_and_new_entries",
        "test_second_process_loads_from_cache",
        "test_sky_illuminance_is_continuous_in_altitude_near_the_ground",
    ),
    "test_properties.py": ("test_cli_renders", "test_sky_frames"),
    "test_rain_mie.py": ("test_packaged_bows_are_what_the_tool_builds",),
    "test_rain_phase.py": (
        "test_moonlit_rain_shows_a_moonbow",
        "test_no_rain_no_bow_the_frame_is_bit_identical",
        "test_sky_draws_supernumeraries_for_drops_of_one_size",
    ),
    "test_rayleigh_ozone.py": ("test_ozone_makes_the_twilight_zenith_blue",),
    "test_readme_snippets.py": ("test_cli_examples_run",),
    "test_real_earth.py": (
        "test_earth_twilight_is_not_too_bright",
        "test_mars_sunset_is_blue_around_the_sun",
        "test_typical_sky_follows_the_measured_mean_curve",
    ),
    "test_scene.py": ("test_a_day_at_one_minute_steps_is_finite_and_never_jumps",),
    "test_single_scattering.py": (
        "test_gl_matches_float64_reference",
        "test_no_nan_every_pixel_written",
    ),
    "test_sky_view.py": ("test_sky_view_matches_direct_lookups_for_other_atmospheres",),
    "test_smooth_layers.py": ("test_reduced_light_alone_equals_the_field[equirect-tiled]",),
    "test_stars.py": ("test_flux_is_the_illuminance[camera1-4096-2048]",),
    "test_time_steps.py": ("test_planets_while_the_time_runs_match_each_instant_computed_alone",),
    "test_viewer_panel.py": ("test_the_clouds_and_the_bortle_class_from_the_panel",),
    "test_viewer_soak.py": ("test_soak_keeps_memory_flat_and_leaks_no_gl_objects",),
}  # fmt: skip


def _module(item) -> str:
    """The test's module relative to tests/ (``test_cli.py``, ``astro/test_stars.py``)."""
    return item.nodeid.split("::", 1)[0].removeprefix("tests/")


def _is_slow(item, slow: dict[str, frozenset[str]]) -> bool:
    names = slow.get(_module(item), frozenset())
    return item.name in names or item.originalname in names


@pytest.hookimpl(tryfirst=True)  # before -m deselects by these markers
def pytest_collection_modifyitems(config, items):
    """Mark the tiers: ``gl`` by fixture or module (GL_FIXTURES, GL_MODULES), ``window`` by
    fixture (WINDOW_FIXTURES), ``slow`` by SLOW_TESTS; ``soak`` is on its test."""
    slow = {module: frozenset(names) for module, names in SLOW_TESTS.items()}
    if _CHECK_TIERS:  # names of SLOW_TESTS that no collected test has (renamed, removed)
        collected = {(_module(i), n) for i in items for n in (i.name, i.originalname)}
        modules = {module for module, _ in collected}
        _unknown.extend(
            f"{module}::{name}"
            for module, names in SLOW_TESTS.items()
            if module in modules
            for name in names
            if (module, name) not in collected
        )
    for item in items:
        fixtures = set(getattr(item, "fixturenames", ()))
        window = bool(fixtures & WINDOW_FIXTURES)
        if window:
            item.add_marker(pytest.mark.window)
        if window or fixtures & GL_FIXTURES or _module(item) in GL_MODULES:
            item.add_marker(pytest.mark.gl)
        if _is_slow(item, slow):
            item.add_marker(pytest.mark.slow)


# SKYDOME_CHECK_TIERS=1: watch what each test does and report what the markers miss.
_CHECK_TIERS = os.environ.get("SKYDOME_CHECK_TIERS", "") not in ("", "0")
_drew = {"now": False, "tables_s": 0.0}
_seen: dict[str, dict] = {}
_unknown: list[str] = []


def _watch_gl() -> None:
    """Note any draw, read-back or GL object made (moderngl's Python classes, patched)."""
    import moderngl

    def watched(cls, name):
        original = getattr(cls, name)

        def call(self, *args, **kwargs):
            _drew["now"] = True
            return original(self, *args, **kwargs)

        setattr(cls, name, call)

    for name in ("program", "texture", "framebuffer", "buffer", "vertex_array"):
        watched(moderngl.Context, name)
    watched(moderngl.VertexArray, "render")
    watched(moderngl.Framebuffer, "read")

    # The session's table builds (load_tables -> precompute; not test_precompute's own calls).
    from skydome.atmosphere import tables

    build = tables.precompute

    def timed_build(*args, **kwargs):
        t0 = time.perf_counter()
        try:
            return build(*args, **kwargs)
        finally:
            _drew["tables_s"] += time.perf_counter() - t0

    tables.precompute = timed_build


if _CHECK_TIERS:
    _watch_gl()

    @pytest.hookimpl(hookwrapper=True)
    def pytest_runtest_protocol(item, nextitem):
        _drew.update(now=False, tables_s=0.0)
        t0 = time.perf_counter()
        yield
        _seen[item.nodeid] = {
            "seconds": time.perf_counter() - t0,
            "tables_s": _drew["tables_s"],
            "drew": _drew["now"],
            "marks": {m.name for m in item.iter_markers()},
        }

    def pytest_terminal_summary(terminalreporter):
        write = terminalreporter.write_line
        terminalreporter.section("tiers (SKYDOME_CHECK_TIERS)")
        findings = 0
        for nodeid, seen in _seen.items():
            s, tables_s, marks = seen["seconds"], seen["tables_s"], seen["marks"]
            problems = []
            if seen["drew"] and "gl" not in marks:
                problems.append("drew with OpenGL, not marked gl")
            if s - tables_s > SLOW_S and not marks & {"slow", "soak"}:
                built = f" ({tables_s:.1f} s building tables)" if tables_s else ""
                problems.append(f"took {s:.1f} s{built}, not marked slow")
            for problem in problems:
                write(f"{nodeid}: {problem}")
                findings += 1
        for name in _unknown:
            write(f"SLOW_TESTS names {name}, which no collected test is")
            findings += 1
        built = sum(seen["tables_s"] for seen in _seen.values())
        write(f"{findings} finding(s) in {len(_seen)} tests; {built:.1f} s building tables")
