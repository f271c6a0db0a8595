"""Mesh sensitivity of the needle scenario: the study ``validation/studies/mesh_sensitivity.toml``.

The built-in needle on the coarse, default and fine presets (``docs/mesh-sensitivity.md``),
run as a study and reported; the same as::

    corneasim study run validation/studies/mesh_sensitivity.toml --out results/mesh-sensitivity
    corneasim study report results/mesh-sensitivity

Usage: ``python validation/mesh_sensitivity.py [--out DIR] [--workers N]``
"""

from __future__ import annotations

import argparse
from pathlib import Path

STUDY = Path(__file__).resolve().parent / "studies" / "mesh_sensitivity.toml"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/mesh-sensitivity"))
    parser.add_argument("--workers", type=int)
    arguments = parser.parse_args()

    import corneasim
    from corneasim.studies.report import write_report

    table = corneasim.study(STUDY, out=arguments.out, workers=arguments.workers, progress=True)
    print(table.drop(columns=["force"]).to_string(index=False))
    print(f"report: {write_report(arguments.out)}")


if __name__ == "__main__":
    main()
