"""The kernel cache as ``x3dpd cache`` shows and clears it (issue 32 item 3; docs/running.md,
"The kernel cache"): each source-hash folder's variants with their manifest entries
(x3dpd.solver.kernel_cache) and sizes on disk, numba's cache of the shared kernels outside it,
the totals; and the deletion of the compiled variants, never outside the cache's kernels/.
"""

from __future__ import annotations

import os
import shutil
from dataclasses import dataclass, field
from pathlib import Path

from x3dpd.solver.kernel_cache import CacheError, read_manifest
from x3dpd.solver.variants import cache_root, source_hash


@dataclass
class VariantRow:
    """One compiled loop in a cache folder: its manifest entry (empty for a loop the manifest
    does not know: compiled before there was one) and its size on disk [bytes]."""

    name: str
    size: int
    entry: dict = field(default_factory=dict)

    @property
    def label(self) -> str:
        return self.entry.get("label") or "(not in the manifest)"


@dataclass
class SourceFolder:
    """The loops compiled from one revision of x3dpd's kernel sources (``kernels/<hash>``)."""

    source_hash: str
    current: bool
    variants: list[VariantRow]
    size: int  # every file of the folder [bytes]
    #: loops generated but never compiled (a Simulation built, its kernels never called):
    #: their sources only, no machine code and no manifest entry
    generated: int = 0


@dataclass
class CacheListing:
    """What ``x3dpd cache`` shows: the folders of a kernel cache, numba's cache of x3dpd's
    shared kernels (outside it), and the totals."""

    root: Path
    source_hash: str  # these sources' folder name (x3dpd.solver.variants.source_hash)
    folders: list[SourceFolder]
    size: int  # every file under the root [bytes]
    shared_files: int
    shared_size: int
    shared_where: str

    @property
    def variants(self) -> list[VariantRow]:
        return [v for f in self.folders for v in f.variants]

    @property
    def compile_seconds(self) -> float:
        """Every compile the manifests record [s]."""
        return sum(
            v.entry.get("compile_seconds_total") or v.entry.get("compile_seconds") or 0.0
            for v in self.variants
        )


def _size(path: Path) -> int:
    try:
        return path.stat().st_size
    except OSError:
        return 0


def _files(folder: Path) -> list[Path]:
    return [p for p in folder.rglob("*") if p.is_file() and not p.is_symlink()]


def _stems(folder: Path) -> list[str]:
    """The stems of the generated loop modules in a source-hash folder."""
    return sorted(p.stem for p in folder.glob("advance_*.py") if "__" not in p.stem)


def _owner(name: str, stems: list[str]) -> str | None:
    """The stem a file of the folder (or its __pycache__) belongs to: its generated sources,
    their bytecode and numba's machine code."""
    for stem in stems:
        if name.startswith((stem + ".", stem + "__")) or name.endswith(f"_{stem}.lock"):
            return stem
    return None


def _check_root(root: Path) -> Path:
    root = Path(root).expanduser()
    if not root.exists():
        raise CacheError(
            f"no kernel cache at {root} (nothing compiled there yet; "
            "X3DPD_CACHE_DIR or --dir selects another)"
        )
    if not root.is_dir():
        raise CacheError(f"{root} is not a directory")
    kernels = root / "kernels"
    if kernels.is_symlink():
        raise CacheError(f"{kernels} is a symbolic link; x3dpd does not follow it")
    if not kernels.is_dir():
        raise CacheError(f"{root} is not an x3dpd kernel cache: it has no kernels/ folder")
    if not os.access(kernels, os.R_OK | os.X_OK):
        raise CacheError(f"cannot read the kernel cache {kernels}: permission denied")
    return root


def list_cache(root: Path | None = None) -> CacheListing:
    """The variants of the kernel cache ``root`` (default :func:`cache_root`) with their
    manifest entries and sizes; a :class:`CacheError` for a missing or unreadable cache."""
    root = _check_root(cache_root() if root is None else root)
    current = source_hash()
    folders = []
    try:
        subdirs = sorted(
            p for p in (root / "kernels").iterdir() if p.is_dir() and not p.is_symlink()
        )
        for sub in subdirs:
            manifest = read_manifest(sub)
            stems = sorted(set(_stems(sub)) | set(manifest["variants"]))
            sizes = dict.fromkeys(stems, 0)
            coded = set()
            files = _files(sub)
            for p in files:
                owner = _owner(p.name, stems)
                if owner is not None:
                    sizes[owner] += _size(p)
                    if p.suffix == ".nbi":
                        coded.add(owner)
            known = set(manifest["variants"]) | coded
            rows = [
                VariantRow(s, sizes[s], manifest["variants"].get(s, {}))
                for s in stems
                if s in known
            ]
            rows.sort(key=lambda r: (r.label, r.name))
            folders.append(
                SourceFolder(
                    sub.name,
                    sub.name == current,
                    rows,
                    sum(_size(p) for p in files),
                    len(set(stems) - known),
                )
            )
        total = sum(_size(p) for p in _files(root))
    except PermissionError as exc:
        raise CacheError(f"cannot read the kernel cache {root}: {exc}") from None
    folders.sort(key=lambda f: (not f.current, f.source_hash))
    n, size, where = shared_kernel_files()
    return CacheListing(root, current, folders, total, n, size, where)


def shared_kernel_files() -> tuple[int, int, str]:
    """numba's own cache of x3dpd's shared kernels (the laws, the contact search, the rigid
    bodies: every kernel of x3dpd's package modules), which numba keeps outside the kernel
    cache: beside their sources (``x3dpd/<package>/__pycache__``) or, with NUMBA_CACHE_DIR set,
    under it. Returns (files, bytes, where)."""
    package = Path(os.path.abspath(__file__)).parents[1]
    base = os.environ.get("NUMBA_CACHE_DIR")
    folders = sorted({p.parent for p in package.rglob("*.py")})
    if base:
        import hashlib

        # numba's _UserProvidedCacheLocator: the source folder's name and the SHA-1 of its path
        places = [
            Path(base) / f"{d.name}_{hashlib.sha1(str(d).encode()).hexdigest()}" for d in folders
        ]
        where = f"under NUMBA_CACHE_DIR={base}"
    else:
        places = [d / "__pycache__" for d in folders]
        where = f"beside x3dpd's sources ({package}/*/__pycache__)"
    files = [p for d in places if d.is_dir() for p in d.iterdir() if p.suffix in (".nbi", ".nbc")]
    return len(files), sum(_size(p) for p in files), where


def clear_cache(root: Path | None = None, *, stale_only: bool = False) -> tuple[int, int]:
    """Delete the compiled variants of the kernel cache ``root`` (default
    :func:`cache_root`): every source-hash folder under ``root/kernels``, or, ``stale_only``,
    those of other x3dpd sources than these. Nothing else is touched: not a file beside the
    folders (the machine's compile-time log, x3dpd.solver.compile_log, stays), nothing outside
    ``root/kernels`` (a symbolic link there is removed, not followed). Returns (folders,
    bytes) deleted; a :class:`CacheError` for a missing or unreadable cache."""
    root = _check_root(cache_root() if root is None else root)
    kernels = (root / "kernels").resolve()
    current = source_hash() if stale_only else None
    removed = freed = 0
    for sub in sorted(kernels.iterdir()):
        if current is not None and sub.name == current:
            continue
        if sub.is_symlink():  # removed, never followed
            sub.unlink()
            size = 0
        elif sub.is_dir():
            size = sum(_size(p) for p in _files(sub))
            shutil.rmtree(sub)
        else:  # the compile-time log (x3dpd.solver.compile_log) and any other file: kept
            continue
        removed += 1
        freed += size
    return removed, freed


__all__ = [
    "CacheListing",
    "SourceFolder",
    "VariantRow",
    "clear_cache",
    "list_cache",
    "shared_kernel_files",
]
