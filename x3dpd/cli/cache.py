"""``x3dpd cache [--dir DIR] [--json] [--clear [--stale] [--yes]]``: the compiled step loops in the
kernel cache, what each cost to compile and who compiled it first; or delete them.

The listing and the deletion are library functions (x3dpd.api.cache); this module prints.
"""

from __future__ import annotations

import json
import os
import sys
from dataclasses import asdict
from pathlib import Path

import click

from x3dpd.api import InputError
from x3dpd.api.cache import cache_root, clear_cache, list_cache


def _mb(size: int) -> str:
    return f"{size / 1e6:.1f} MB"


def _short(text: str, width: int) -> str:
    return text if len(text) <= width else text[: width - 3] + "..."


def _where(root: Path, given: str | None) -> str:
    if given is not None:
        return f"kernel cache {root} (--dir)"
    if os.environ.get("X3DPD_CACHE_DIR"):
        return f"kernel cache {root} (X3DPD_CACHE_DIR)"
    return f"kernel cache {root} (the default; X3DPD_CACHE_DIR or --dir selects another)"


def _variants(n: int) -> str:
    return f"{n} variant" + ("" if n == 1 else "s")


def _print_listing(listing, header: str, every: bool) -> None:
    click.echo(header)
    if not any(f.current for f in listing.folders):
        click.echo(f"sources {listing.source_hash} (this x3dpd's sources): nothing compiled yet")
    for folder in listing.folders:
        state = "this x3dpd's sources" if folder.current else "other sources: stale"
        never = f" (and {folder.generated} generated, never compiled)" if folder.generated else ""
        click.echo(
            f"sources {folder.source_hash} ({state}): {_variants(len(folder.variants))}{never}, "
            f"{_mb(folder.size)}"
            + ("" if folder.current or every else "; --all lists them, --clear --stale deletes")
        )
        if not folder.variants or not (folder.current or every):
            continue
        click.echo(
            f"  {'compile s':>9}  {'n':>2}  {'size':>8}  {'compiled':<10}  {'loads':>5}  "
            f"{'first user':<50}  variant (effects)"
        )
        for row in folder.variants:
            e = row.entry
            seconds = e.get("compile_seconds_total") or e.get("compile_seconds")
            click.echo(
                f"  {'-' if seconds is None else f'{seconds:.1f}':>9}  "
                f"{e.get('compiles', '-'):>2}  {_mb(row.size):>8}  "
                f"{(e.get('compiled') or '-')[:10]:<10}  {e.get('loads', '-'):>5}  "
                f"{_short(e.get('first_user') or '-', 50):<50}  "
                f"{e.get('label') or row.name + ' (not in the manifest)'}"
            )
    unknown = sum(1 for v in listing.variants if not v.entry)
    click.echo(
        f"total: {_variants(len(listing.variants))}, {_mb(listing.size)} on disk, "
        f"{listing.compile_seconds:.1f} s of compiling recorded"
        + (f" ({unknown} not in a manifest: compiled before there was one)" if unknown else "")
    )
    click.echo(
        f"numba's cache of x3dpd's shared kernels: {listing.shared_files} files, "
        f"{_mb(listing.shared_size)}, {listing.shared_where}; numba renews it when a source "
        "changes, and --clear leaves it"
    )


def _as_json(listing) -> str:
    return json.dumps(
        {
            "root": str(listing.root),
            "source_hash": listing.source_hash,
            "size": listing.size,
            "compile_seconds": listing.compile_seconds,
            "folders": [asdict(f) for f in listing.folders],
            "shared_kernels": {
                "files": listing.shared_files,
                "size": listing.shared_size,
                "where": listing.shared_where,
            },
        },
        indent=1,
    )


@click.command("cache")
@click.option(
    "--dir",
    "directory",
    type=click.Path(file_okay=False, path_type=Path),
    default=None,
    help="The kernel cache to show or clear (default: $X3DPD_CACHE_DIR, else ~/.cache/x3dpd).",
)
@click.option("--all", "every", is_flag=True, help="List the variants of other x3dpd sources too.")
@click.option("--json", "as_json", is_flag=True, help="Print the listing as JSON (every folder).")
@click.option(
    "--clear",
    is_flag=True,
    help="Delete the compiled variants (every kernels/ folder of the cache; nothing else).",
)
@click.option(
    "--stale", is_flag=True, help="With --clear: only the variants of other x3dpd sources."
)
@click.option("--yes", "-y", is_flag=True, help="With --clear: do not ask.")
def cache(
    directory: Path | None, every: bool, as_json: bool, clear: bool, stale: bool, yes: bool
) -> None:
    """List the kernel cache: each compiled step-loop variant, its effects, its compile
    seconds, its size on disk, who compiled it first; and the total. Variants of other x3dpd
    sources (an earlier version: stale, never loaded again) are counted, listed with --all.

    A scene's first run compiles its variant (docs/engine.md, "Compile time"); later runs of
    any scene with the same effects load it. --clear deletes the compiled variants (asking
    first, or --yes); the next run of each scene compiles again.
    """
    if (stale or yes) and not clear:
        raise InputError("--stale and --yes go with --clear")
    if clear and as_json:
        raise InputError("--json lists; it does not go with --clear")
    root = Path(directory).expanduser() if directory is not None else cache_root()
    listing = list_cache(root)  # a missing or unreadable cache: exit 2, nothing deleted
    if not clear:
        if as_json:
            click.echo(_as_json(listing))
        else:
            where = _where(root, None if directory is None else str(directory))
            _print_listing(listing, where, every)
        return
    folders = [f for f in listing.folders if not (stale and f.current)]
    n = sum(len(f.variants) for f in folders)
    size = sum(f.size for f in folders)
    what = f"{_variants(n)} ({_mb(size)}) in {listing.root / 'kernels'}"
    if not folders:
        click.echo(f"nothing to delete in {listing.root / 'kernels'}")
        return
    if not yes:
        if not sys.stdin.isatty():
            raise InputError(f"--clear would delete {what}; add --yes to delete them")
        if not click.confirm(f"delete {what}?", default=False):
            click.echo("nothing deleted")
            return
    removed, freed = clear_cache(root, stale_only=stale)
    click.echo(f"deleted {what}: {removed} source folders, {_mb(freed)}")
