"""Command line interface: ``ccu deploy``, ``ccu path``, ``ccu info``.

Every command takes a design TOML file (see ``docs/design-files.md``). Errors in the input are
printed as one line naming the cause and the value, with exit status 2.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

__all__ = ["main"]


def _load(path: str):
    from compas_ccu.design import load_design

    return load_design(path).build()


def _cmd_deploy(args) -> int:
    from compas_ccu.io import write_compas_json, write_obj, write_structure_json

    model = _load(args.design)
    structure = model.deploy(args.alpha)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    files = [
        write_structure_json(structure, out / "structure.json"),
        write_obj(structure, out / "structure.obj"),
        write_compas_json(structure, out / "structure.compas.json"),
    ]
    m = structure.metrics
    _say(
        args,
        f"deployed {model.design.name} to alpha = {structure.alpha:g} deg "
        f"(limit {model.alpha_limit:.4g} deg): span {m['span']:.4f} m, "
        f"rise {m['rise']:.4f} m",
    )
    _say(
        args,
        f"invariants (relative to size {m['size']:.3f} m): isometry "
        f"{m['isometry_relative']:.1e}, quad planarity {m['quad_planarity_relative']:.1e}, "
        f"hinges {m['hinge_gap_relative']:.1e}, mirror {m['mirror_error_relative']:.1e}, "
        f"crease planarity {m['crease_planarity_max_relative']:.1e}",
    )
    for f in files:
        _say(args, f"wrote {f}")
    return 0


def _cmd_path(args) -> int:
    import numpy as np

    from compas_ccu.io import write_path_table, write_structure_json

    model = _load(args.design)
    target = model.alpha_design if args.alpha is None else args.alpha
    if args.steps < 1:
        raise SystemExit(_fail(f"--steps must be >= 1, got {args.steps}"))
    alphas = np.linspace(0.0, target, args.steps + 1)
    structures = model.path(alphas)
    out = Path(args.out)
    states = out / "states"
    states.mkdir(parents=True, exist_ok=True)
    for k, s in enumerate(structures):
        write_structure_json(s, states / f"state_{k:04d}.json")
    table = write_path_table(structures, out / "path.csv")
    worst = max(s.metrics["crease_planarity_max"] for s in structures)
    _say(
        args,
        f"{len(structures)} states from alpha = 0 to {target:g} deg; largest crease "
        f"planarity deviation along the path {worst:.2e} m",
    )
    _say(args, f"wrote {table} and {len(structures)} files in {states}")
    return 0


def _cmd_info(args) -> int:
    from compas_ccu.io import flat_footprint

    model = _load(args.design)
    s = model.deploy()
    m = s.metrics
    kinds: dict = {}
    for c in s.creases:
        kinds[c["kind"]] = kinds.get(c["kind"], 0) + 1
    width, height = flat_footprint(s)
    lines = [
        f"design            {model.design.name}",
        f"plates            {len(s.plate_ids)}",
        f"creases           {len(s.creases)}"
        + (f" ({', '.join(f'{v} {k}' for k, v in sorted(kinds.items()))})" if kinds else ""),
        f"segments          {model.segments} per crease",
        f"design alpha      {model.alpha_design:g} deg at reference vertex {model.reference}",
        f"deployment limit  {model.alpha_limit:.4f} deg (crease segment {model.limit_vertex} "
        "perpendicular to its plane)",
        f"overlap limit     {model.overlap_alpha:.4f} deg (largest alpha before a crease "
        "overlaps itself)",
        f"span              {m['span']:.4f} m (leading crease chord)",
        f"rise              {m['rise']:.4f} m",
        "bounding box      " + " x ".join(f"{v:.3f}" for v in m["bounding_box"]) + " m",
        f"flat stack        {width:.3f} x {height:.3f} m footprint",
        f"invariants        max relative error {s.max_invariant_error:.1e}, crease planarity "
        f"{m['crease_planarity_max']:.1e} m",
    ]
    print("\n".join(lines))
    return 0


def _say(args, text: str) -> None:
    if not getattr(args, "quiet", False):
        print(text)


def _fail(message: str) -> int:
    print(f"ccu: error: {message}", file=sys.stderr)
    return 2


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="ccu",
        description="Curved-crease unfolding: deploy CCU designs exactly and write the results.",
    )
    from compas_ccu import __version__

    parser.add_argument("--version", action="version", version=f"compas_ccu {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True

    p = sub.add_parser(
        "deploy",
        help="deploy a design to one reflection angle",
        description="Deploy DESIGN to --alpha and write structure.json "
        "(SPEC §4), structure.obj and structure.compas.json into --out.",
    )
    p.add_argument("design", help="design TOML file")
    p.add_argument(
        "--alpha",
        type=float,
        default=None,
        help="reference reflection angle in degrees (default: the design alpha)",
    )
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--quiet", action="store_true", help="print nothing on success")
    p.set_defaults(func=_cmd_deploy)

    p = sub.add_parser(
        "path",
        help="deploy along a path from the flat stack",
        description="Deploy DESIGN from alpha = 0 to the design alpha (or "
        "--alpha) in --steps equal steps; write states/state_NNNN.json and "
        "path.csv (alpha, span, rise, planarity per state).",
    )
    p.add_argument("design", help="design TOML file")
    p.add_argument("--steps", type=int, default=10, help="number of steps (default 10)")
    p.add_argument("--alpha", type=float, default=None, help="final alpha, degrees")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--quiet", action="store_true", help="print nothing on success")
    p.set_defaults(func=_cmd_path)

    p = sub.add_parser(
        "info",
        help="print the key figures of a design",
        description="Print plates, creases by kind, design alpha, deployment "
        "limit, span, rise and the flat stack footprint of DESIGN.",
    )
    p.add_argument("design", help="design TOML file")
    p.set_defaults(func=_cmd_info)
    return parser


def main(argv=None) -> int:
    """Entry point of the ``ccu`` command."""
    from compas_ccu.errors import CCUError

    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except CCUError as exc:
        return _fail(str(exc))


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
