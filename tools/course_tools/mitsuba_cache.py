"""Mitsuba 3's renders and the regions the prototypes trace for them, kept in the
per-user reference cache (reference_cache.py) under what makes them: for the checks
(tests/python/path_checks.py) and the benches alike."""

from __future__ import annotations

import dataclasses
import io
import os
from pathlib import Path

import numpy as np

from course_tools import python_imports, reference_cache
from course_tools.paths import ROOT


def scene_fingerprint(value) -> str:
    """The parsed scene as text, with each file it reads (meshes, textures, skies) as
    the digest of its bytes instead of its path, so that the same scene in another
    clone or folder has the same fingerprint; where a line was read is left out."""
    if dataclasses.is_dataclass(value):
        fields = {f.name: getattr(value, f.name) for f in dataclasses.fields(value)
                  if f.name not in ("line", "written_path")}
        if type(value).__name__ == "Scene":
            fields.pop("path")  # the file itself: what it says is in the fields
        return f"{type(value).__name__}({scene_fingerprint(fields)})"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k!r}: {scene_fingerprint(v)}"
                               for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(scene_fingerprint(v) for v in value) + "]"
    if isinstance(value, Path):
        return f"file {reference_cache.file_digest(value)}"
    return repr(value)


def translating_sources() -> list[Path]:
    """mitsuba_reference.py and every python_prototypes module it imports, at any depth
    (python_imports.imported_modules, which finds a starter's modules the same way), sorted:
    what turns a scene into Mitsuba's."""
    module = ROOT / "python_prototypes" / "mitsuba_reference.py"
    return sorted({module, *python_imports.imported_modules(module, [ROOT])})


def kept_render(scene, width: int, height: int, spp: int, bounces: int, seed: int = 0,
                variant: str = "scalar_rgb") -> np.ndarray:
    """Mitsuba 3's render (mitsuba_reference.render_mitsuba: linear RGB, row 0 at the
    top), kept under what makes it: the scene with its files' bytes, the size, samples,
    depth, seed, variant, Mitsuba's and Dr.Jit's versions, the cores, and the prototypes
    that translate it (translating_sources: only those, so that a new prototype or
    figure script beside them keeps every kept render)."""
    import drjit
    import mitsuba
    from python_prototypes import mitsuba_reference
    name = reference_cache.key(
        "mitsuba render", mitsuba.__version__, drjit.__version__, variant, width, height,
        spp, bounces, seed, os.cpu_count(), scene_fingerprint(scene),
        *translating_sources()) + ".npy"
    kept = reference_cache.fetch(name)
    if kept is not None:
        return np.load(io.BytesIO(kept), allow_pickle=False)
    image, _ = mitsuba_reference.render_mitsuba(scene, width, height, spp, bounces,
                                                seed=seed, variant=variant)
    image = np.ascontiguousarray(np.asarray(image, dtype=np.float32)[..., :3])
    payload = io.BytesIO()
    np.save(payload, image, allow_pickle=False)
    reference_cache.store(name, payload.getvalue())
    return image


def kept_region_masks(scene, width: int, height: int) -> dict:
    """mitsuba_reference.region_masks, kept under the scene's fingerprint, the size and the
    prototypes that trace it: numpy takes seconds a picture for a mesh (the teapot at
    160 x 160: 17 s)."""
    from python_prototypes import mitsuba_reference
    name = reference_cache.key("region masks", scene_fingerprint(scene), width, height,
                               *translating_sources()) + ".npz"
    kept = reference_cache.fetch(name)
    if kept is not None:
        with np.load(io.BytesIO(kept)) as stored:
            return {region: stored[region] for region in stored.files}
    masks = mitsuba_reference.region_masks(scene, width, height)
    payload = io.BytesIO()
    np.savez(payload, **masks)
    reference_cache.store(name, payload.getvalue())
    return masks
