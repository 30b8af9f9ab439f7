#!/usr/bin/env python3
"""Checks the feature pins of crates/gecaro-py/Cargo.toml.

maturin builds gecaro-py alone, and cargo enables a dependency's features from
the packages of one build only. Where a dependency of gecaro-py gets other
features in that build than in `cargo test --workspace`, it is compiled a
second time, and with it everything above it (serde, nalgebra, faer, the
gecaro crates: minutes of CI). The pins in gecaro-py's Cargo.toml ask for the
workspace's features; this script names any package whose features differ, so
that a dependency update which stales a pin fails here, with the fix, instead
of slowing CI unseen.

Usage: python3 crates/gecaro-py/feature_pins.py (from anywhere in the
repository; needs cargo). Exit status 1 names the packages to pin.
"""

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def features(*selection: str) -> dict[str, set[str]]:
    """Each package's enabled features in a build of `selection`."""
    output = subprocess.run(
        ["cargo", "tree", "--quiet", "--locked", "--prefix", "none", "--format", "{p} {f}", *selection],
        cwd=ROOT,
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    found: dict[str, set[str]] = {}
    for line in output.splitlines():
        words = [w for w in line.split() if w not in ("(*)", "(proc-macro)")]
        if len(words) < 2:
            continue
        package = f"{words[0]} {words[1]}"
        last = words[-1]
        enabled = last if len(words) > 2 and not last.startswith("(") else ""
        found.setdefault(package, set()).add(enabled)
    return found


def main() -> int:
    workspace = features("--workspace")
    python = features("--package", "gecaro-py", "--edges", "normal,build")
    stale = sorted(
        (package, python[package], workspace[package])
        for package in python
        if package in workspace and python[package] != workspace[package]
    )
    for package, alone, together in stale:
        print(
            f"{package}: features {sorted(alone)} when gecaro-py is built alone, "
            f"{sorted(together)} in the workspace's tests: pin the missing ones in "
            "crates/gecaro-py/Cargo.toml",
            file=sys.stderr,
        )
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main())
