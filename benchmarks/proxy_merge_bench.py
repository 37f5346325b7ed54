"""The convex proxy's merge, side by side: CoACD's own merge against ours (collision.merge_hulls) on the same meshes,
per prompt the CPU seconds, the hull count and the union / mesh volume (the gate 'proxy hugs mesh' wants 0.9-1.6).

    python -m benchmarks.proxy_merge_bench [PROMPT ...] [--quality draft] [--json]
"""

from __future__ import annotations

import time

import typer

from contracts.request import AssetRequest
from flows.cli.apps import console, emit_json
from tasks.geometry import pipeline, sources
from tasks.geometry.collision import convex_parts, union_volume

DEFAULT_PROMPTS = ("a plush turtle", "a dog bed", "a crumpled sheet of paper", "a knitted beanie", "a pretzel",
                   "a foam puzzle floor tile", "a teddy bear", "a rubber duck", "a latex glove", "a croissant")

app = typer.Typer(add_completion=False, pretty_exceptions_enable=False)


def compare(text: str, quality: str) -> dict:
    """One prompt's mesh through both merges."""
    settings = pipeline.settings_from_contract(quality)  # type: ignore[arg-type]
    mesh, _ = sources.build_mesh(AssetRequest(text=text), settings)
    m = pipeline.arrays_to_mesh(mesh)
    row: dict = {"text": text, "faces": len(m.faces)}
    for merge in ("coacd", "volume"):
        c0 = time.process_time()
        parts = convex_parts(m, settings.coacd.model_copy(update={"merge": merge}))
        row[merge] = {"cpu_s": round(time.process_time() - c0, 2), "hulls": len(parts),
                      "union_over_mesh": round(union_volume(parts) / float(m.volume), 3)}
    return row


@app.command()
def main(prompts: list[str] = typer.Argument(None), quality: str = "draft", as_json: bool = typer.Option(False, "--json")) -> None:
    """Both merges on each prompt's mesh; the summed CPU seconds and their ratio."""
    rows = []
    for text in prompts or DEFAULT_PROMPTS:
        rows.append(compare(text, quality))
        if not as_json:
            r = rows[-1]
            console.print(f"{text}: coacd {r['coacd']} | ours {r['volume']}")
    total = {m: round(sum(r[m]["cpu_s"] for r in rows), 2) for m in ("coacd", "volume")}
    summary = {"quality": quality, "prompts": len(rows), "cpu_s": total,
               "speedup": round(total["coacd"] / max(total["volume"], 1e-9), 2),
               "max_union_over_mesh": {m: max(r[m]["union_over_mesh"] for r in rows) for m in ("coacd", "volume")}}
    if as_json:
        emit_json({"rows": rows, "summary": summary})
    else:
        console.print(summary)


if __name__ == "__main__":
    app()
