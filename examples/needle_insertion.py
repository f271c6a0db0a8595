"""Needle insertion into the cornea from Python, in a few lines.

The needle paper's model (``corneasim show needle``) is run with one call; the history
comes back as arrays (units in the column names) and the summary as a dict, and
nothing is written to disk unless ``out_dir`` is given. Overrides use the same
``KEY=VALUE`` form as ``corneasim run --set``.

Run it: ``python examples/needle_insertion.py [coarse|default|fine]``
"""

import sys

import corneasim


def main(preset: str = "coarse") -> dict:
    """Insert the needle at 1 mm/s and 5 mm/s; print peak force and the validation error."""
    results = {}
    for speed in (1.0, 5.0):
        result = corneasim.run_scenario("needle", [
            f"mesh.preset={preset}",
            f"instrument.motion.insertion.rate={speed}",
            f"solver.end_time={0.7 / speed}",
            f"validation.y_column=experiment_{speed:g}mm_s_N",
        ])
        history, summary = result.history, result.summary
        validation = summary.get("validation") or {}
        print(f"{speed:g} mm/s: peak force {summary['peak_force_N']:.3f} N at depth "
              f"{history['depth_mm'][history['force_N'].argmax()]:.3f} mm; RMSE against the experiment "
              f"{validation.get('rmse_N', float('nan')):.3f} N; punctures: "
              + ", ".join(f"{p['event']} at {p['depth_mm']:.3f} mm" for p in summary["punctures"]))
        results[speed] = result
    return results


if __name__ == "__main__":
    main(*sys.argv[1:])
