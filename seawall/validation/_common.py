"""Helpers shared by the validation entries."""


def pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def run_to_the_end_or_the_stop(sim, t_end, progress=False):
    """``(result, InstabilityError or None)``: the run to ``t_end``, or, if the stability guard stops
    it, what it sampled up to the stop, so an entry can report its rows up to there and name the stop."""
    from ..errors import InstabilityError

    try:
        return sim.run(t_end, progress=progress), None
    except InstabilityError as exc:
        return sim.result(sim.summary_so_far()), exc


def rows_side_by_side(results, labels):
    """Markdown table of the rows of several stored results of one entry family (the same rows in
    the same order), each cell the value with its error and "fail" where it misses its target.
    ``results``: the stored result dicts; ``labels``: a column title for each."""
    first = results[0]["rows"]
    if any(len(r["rows"]) != len(first) for r in results):
        raise ValueError("the results do not have the same rows")
    lines = ["| quantity | reference | " + " | ".join(labels) + " | target |", "| --- " * (len(labels) + 3) + "|"]
    for k, ref in enumerate(first):
        cells = []
        for res in results:
            r = res["rows"][k]
            relative = r["error_kind"] == "relative"
            err = "--" if r["error"] is None else (f"{100 * r['error']:+.1f} %" if relative else f"{r['error']:+.3f}")
            value = "--" if r["value"] is None else r["format"].format(r["value"])
            cells.append(f"{value} ({err})" + ("" if r["pass"] else " fail"))
        tol = f"{100 * ref['tolerance']:g} %" if ref["error_kind"] == "relative" else f"{ref['tolerance']:g}"
        quantity = ref["quantity"].replace("|", "\\|")     # |p*| would end the cell
        lines.append(f"| {quantity} | {ref['format'].format(ref['reference_value'])} | "
                     + " | ".join(cells) + f" | {tol} |")
    return "\n".join(lines)
