"""Which two-word WordNet compounds of a head noun L0 reads as a named object, though the entry does not list them.

    python -m benchmarks.compound_audit hat,helmet,suit,kite [--json]

For each head noun, every WordNet noun 'X head' (index.noun, one modifier) that no lexicon entry lists is read as
'a X head'; those read as a named object (fallback level exact or synonym) are printed with the entry they built.
Since session 56 a compound whose modifier is a noun is read by analogy (tasks.geometry.concepts._unlisted_compound:
'a sweat suit' is built as the business suit and says so); what is left here is read through a qualifier (a colour,
'black kite'; a material), a WordNet synonym the lexicon lists, or a form the reading does not split (hyphenated or
possessive modifiers, 'ten-gallon hat', "bishop's hat"): a review list for the lexicon, not a pass/fail test.
"""

from __future__ import annotations

import typer

from contracts.lexicon import load_lexicon
from flows.cli.apps import emit_json, results
from tasks.geometry import catalogue
from tasks.geometry.wordnet import data_dir


def compounds(head: str) -> list[str]:
    """WordNet nouns 'X head' with one modifier, readable ('sweat suit')."""
    with (data_dir() / "index.noun").open(encoding="utf-8") as f:
        lemmas = [line.split()[0] for line in f if not line.startswith(" ")]
    return sorted({w.replace("_", " ") for w in lemmas if w.endswith("_" + head) and w.count("_") == 1})


def audit(heads: list[str]) -> list[dict[str, str]]:
    """The compounds of each head read as a named object that no entry lists."""
    listed = {n for e in load_lexicon().entries.values() for n in e.nouns}
    rows = []
    for head in heads:
        for c in compounds(head):
            if c in listed:
                continue
            design = catalogue.design_from_text(f"a {c}")
            level = design.concept.fallback_level if design.concept else None
            if level in ("exact", "synonym"):
                rows.append({"head": head, "compound": c, "entry": str(design.entry), "level": str(level)})
    return rows


app = typer.Typer(add_completion=False, pretty_exceptions_enable=False)


@app.command()
def compound_audit(heads: str = typer.Argument(..., help="head nouns, comma-separated"),
                   json_out: bool = typer.Option(False, "--json", help="print the rows as JSON on stdout")) -> None:
    """Two-word WordNet compounds of each head noun that L0 reads as a named object."""
    rows = audit([h.strip() for h in heads.split(",") if h.strip()])
    if json_out:
        emit_json(rows)
        return
    for r in rows:
        results.print(f"{r['head']:10s} {r['compound']:30s} -> {r['entry']} [{r['level']}]", markup=False,
                      highlight=False)
    results.print(f"{len(rows)} compounds read as a named object", markup=False, highlight=False)


if __name__ == "__main__":
    app()
