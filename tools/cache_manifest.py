"""Write tests/data/cache_builders.json: each cached product's version and the SHA-256 of the
builder files its ``CacheSpec`` declares (``skydome.core.cache``).

The cache keys hash the shaders and the parameters, not the Python: a change of a builder
file that changes what a product computes must come with a bump of its spec's ``version``.
``tests/test_cache.py`` compares this manifest with the code and fails when a builder file's
digest changed while its version did not, or when the manifest is out of date.

    python tools/cache_manifest.py                 # rewrite it (after bumping versions)
    python tools/cache_manifest.py --keep-version  # rewrite it for edits that cannot change
                                                   # a product (a comment, a docstring)
    python tools/cache_manifest.py --check         # exit 1, printing what differs
"""

from __future__ import annotations

import argparse
import importlib
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MANIFEST = ROOT / "tests" / "data" / "cache_builders.json"
REFRESH = "python tools/cache_manifest.py"

if str(ROOT / "src") not in sys.path:  # hash this checkout's files, not an installed copy's
    sys.path.insert(0, str(ROOT / "src"))

from skydome.core.cache import PACKAGE_ROOT, CacheSpec  # noqa: E402


def declared_specs() -> dict[str, tuple[str, CacheSpec]]:
    """Every CacheSpec that a module of the package holds at its top level, by spec name:
    (module name, spec). The modules are those whose source mentions ``CacheSpec(``."""
    specs: dict[str, tuple[str, CacheSpec]] = {}
    for path in sorted(PACKAGE_ROOT.rglob("*.py")):
        rel = path.relative_to(PACKAGE_ROOT).with_suffix("")
        if rel.as_posix() == "core/cache" or "CacheSpec(" not in path.read_text("utf-8"):
            continue
        module = ".".join(("skydome", *rel.parts)).removesuffix(".__init__")
        for value in vars(importlib.import_module(module)).values():
            if isinstance(value, CacheSpec):
                other = specs.setdefault(value.name, (module, value))
                if other != (module, value):
                    raise ValueError(
                        f"two cache specs are named {value.name!r}: {other[0]}, {module}"
                    )
    return specs


def manifest(specs: dict[str, tuple[str, CacheSpec]]) -> dict:
    """The manifest's content for ``specs``."""
    return {
        name: {"module": module, "version": spec.version, "files": spec.builder_digests()}
        for name, (module, spec) in sorted(specs.items())
    }


def problems(recorded: dict, specs: dict[str, tuple[str, CacheSpec]]) -> list[str]:
    """What differs between the ``recorded`` manifest and the code, one sentence each."""
    out = []
    for name, (module, spec) in sorted(specs.items()):
        old, files = recorded.get(name), spec.builder_digests()
        where = f"src/{module.replace('.', '/')}.py"
        if old is None:
            out.append(f"cache spec {name!r} ({where}) is not in the manifest: run {REFRESH}")
            continue
        changed = sorted(f for f in files if old["files"].get(f, files[f]) != files[f])
        if spec.version == old["version"] and changed:
            out.append(
                f"{', '.join(changed)} changed but cache spec {name!r} is still version "
                f"{spec.version}: bump its version in {where} (users' cached {name} are then "
                f"rebuilt) and run {REFRESH}; only if the edit cannot change what is cached "
                f"(a comment, a docstring), run {REFRESH} --keep-version instead"
            )
        elif spec.version < old["version"]:
            out.append(
                f"cache spec {name!r} went back from version {old['version']} to "
                f"{spec.version} in {where}: versions only go up"
            )
        elif spec.version > old["version"] or files.keys() != old["files"].keys():
            out.append(f"the manifest is out of date for {name!r}: run {REFRESH}")
    out += [
        f"the manifest lists {name!r}, which no module declares: run {REFRESH}"
        for name in sorted(recorded.keys() - specs.keys())
    ]
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="only compare; exit 1 on a change")
    parser.add_argument(
        "--keep-version",
        action="store_true",
        help="record changed builder files without a version bump (edits that change no output)",
    )
    args = parser.parse_args(argv)
    specs = declared_specs()
    if args.check:
        recorded = json.loads(MANIFEST.read_text("utf-8")) if MANIFEST.exists() else {}
        found = problems(recorded, specs)
        print("\n".join(found) or f"{MANIFEST.relative_to(ROOT)} is current")
        return 1 if found else 0
    recorded = json.loads(MANIFEST.read_text("utf-8")) if MANIFEST.exists() else {}
    bumps = [p for p in problems(recorded, specs) if "back from" in p]
    bumps += [p for p in problems(recorded, specs) if "bump" in p and not args.keep_version]
    if bumps:  # refreshing would hide them: the version must change first
        print("\n".join(bumps), file=sys.stderr)
        return 1
    MANIFEST.write_text(json.dumps(manifest(specs), indent=1, sort_keys=True) + "\n", "utf-8")
    print(f"wrote {MANIFEST.relative_to(ROOT)} ({len(specs)} cached products)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
