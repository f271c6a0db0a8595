"""``corneasim mesh``: Eye geometry and meshes: build, check, export, preview."""

from __future__ import annotations

import argparse
from pathlib import Path

HELP = "Eye geometry and meshes: build, check, export, preview."

DESCRIPTION = """Build the parametric eye mesh (needle: axisymmetric quads; trephine: 3D half model
in hexahedra), or read a mesh file (.inp, .msh, .vtu, .vtk, .xdmf) or a scenario (.toml);
print its quality report; write it (--out, format from the suffix: .inp, .vtu, .vtk,
.xdmf) and a picture (--preview). Lengths in mm.

`corneasim mesh convert IN OUT` writes the linear mesh that IN is read as: 8-node quads,
20-node hexahedra and 10-node tetrahedra split into 4-node quads and 8-node hexahedra
through their midside nodes (what a run does on import), sets kept."""

EPILOG = """example: corneasim mesh needle --preset coarse --preview needle.png
conversion: corneasim mesh convert cap_c3d20r.inp cap_c3d8.inp"""


def register(commands: argparse._SubParsersAction) -> None:
    """Add the ``mesh`` command."""
    parser = commands.add_parser("mesh", help=HELP, description=HELP + "\n\n" + DESCRIPTION, epilog=EPILOG,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("source", metavar="SOURCE",
                        help="needle, trephine, a mesh file or a scenario .toml file; or convert")
    parser.add_argument("files", nargs="*", metavar="IN OUT", help="with convert: the mesh file to read and "
                        "the file to write (format from the suffix)")
    parser.add_argument("--strategy", choices=("umbrella", "vertical", "horizontal"),
                        help="3D meshing strategy (trephine or a 3D scenario; default umbrella)")
    parser.add_argument("--preset", choices=("coarse", "default", "fine"),
                        help="mesh density (needle, trephine or a scenario; default: default)")
    parser.add_argument("--geometry", metavar="TOML", help="eye dimensions in mm (keys of EyeGeometry)")
    parser.add_argument("--out", metavar="FILE", help="write the mesh (.inp, .vtu, .vtk, .xdmf)")
    parser.add_argument("--preview", metavar="PNG", help="write a picture of the mesh")
    parser.add_argument("--wave-speed", type=float, metavar="MM_PER_S",
                        help="dilatational wave speed for the stable time step (mm/s)")
    parser.set_defaults(handler=run)


def build(source: str, strategy: str, preset: str, geometry_file: str | None):
    """The mesh named by ``source`` (built-in eye, mesh file or scenario)."""
    from corneasim.errors import InputError
    from corneasim.mesh import EyeGeometry
    from corneasim.schema import load_toml, validate

    geometry = validate(EyeGeometry, load_toml(geometry_file), geometry_file) if geometry_file else EyeGeometry()
    if source == "needle":
        from corneasim.mesh import mesh_axisymmetric

        return mesh_axisymmetric(geometry, preset or "default")
    if source == "trephine":
        from corneasim.mesh import mesh_3d

        return mesh_3d(geometry, strategy or "umbrella", preset or "default")
    path = Path(source)
    if path.suffix.lower() == ".toml":
        from corneasim.scenarios import make_mesh
        from corneasim.scenarios import load_scenario

        overrides = [f"mesh.{key}={value}" for key, value in (("preset", preset), ("strategy", strategy)) if value]
        scenario, _, base_dir = load_scenario(str(path), overrides)
        if geometry_file:
            scenario = scenario.model_copy(update={"mesh": scenario.mesh.model_copy(update={"geometry": geometry})})
        return make_mesh(scenario, base_dir)
    if not path.exists():
        raise InputError(f"{source}: not needle, trephine or an existing mesh or scenario file")
    if preset or strategy or geometry_file:
        raise InputError(f"{source}: --preset, --strategy and --geometry apply to needle, trephine or a scenario, "
                         "not to a mesh file")
    from corneasim.mesh import read_mesh

    return read_mesh(path)


def convert(source: str, target: str) -> int:
    """Read ``source`` (quadratic cells split into linear ones), write it to ``target``; print what was done."""
    import warnings

    from corneasim.mesh import MeshConversion, read_mesh, write_mesh

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", MeshConversion)
        mesh = read_mesh(source)
    notes = [str(warning.message) for warning in caught if issubclass(warning.category, MeshConversion)]
    print("\n".join(notes) or f"{source}: {mesh.n_elements} linear {mesh.cell_type} elements (nothing to split)")
    print(f"wrote {write_mesh(mesh, target)}")
    return 0


def run(arguments: argparse.Namespace) -> int:
    """Build or read the mesh, report its quality, write the requested files."""
    import warnings

    from corneasim.errors import InputError
    from corneasim.mesh import MeshConversion, check_elements, quality_report, write_mesh

    if arguments.source == "convert":
        if len(arguments.files) != 2:
            raise InputError("mesh convert: expected two files, IN and OUT, e.g. corneasim mesh convert a.inp b.inp")
        return convert(*arguments.files)
    if arguments.files:
        raise InputError(f"mesh: unexpected arguments {' '.join(arguments.files)} (only 'mesh convert' takes two files)")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", MeshConversion)
        mesh = build(arguments.source, arguments.strategy, arguments.preset, arguments.geometry)
    for warning in caught:
        print(warning.message)
    check_elements(mesh)
    report = quality_report(mesh, arguments.wave_speed)
    print("\n".join(report.lines()))
    print("sets: " + ", ".join(
        [f"node {name} ({len(v)})" for name, v in mesh.node_sets.items()]
        + [f"surface {name} ({len(v)})" for name, v in mesh.surface_sets.items()]
        + [f"element {name} ({len(v)})" for name, v in mesh.element_sets.items()]
    ))
    if arguments.out:
        print(f"wrote {write_mesh(mesh, arguments.out)}")
    if arguments.preview:
        from corneasim.mesh import write_preview

        if arguments.source == "needle":
            title = f"needle insertion eye (axisymmetric), preset {arguments.preset or 'default'}"
        elif arguments.source == "trephine":
            title = (f"trephination half model, {arguments.strategy or 'umbrella'} strategy, "
                     f"preset {arguments.preset or 'default'}")
        else:
            title = Path(arguments.source).name
        title += f": {mesh.n_elements} elements"
        if report.refined_count is not None:
            title += f", {report.refined_count} in the refined set"
        print(f"wrote {write_preview(mesh, arguments.preview, title=title)}")
    return 0
