"""Unknown nouns by meaning (WordNet), and an object built by analogy always says so: the first console line, the
concept's record, the card's box, and --strict-concept refusing it with nothing written."""

from __future__ import annotations

from pathlib import Path

import pytest

from contracts.lexicon import load_lexicon
from tasks.geometry import analogy, concepts
from tasks.geometry.catalogue import design_from_text
from tasks.geometry.concepts import SHAPE_WORDS, noun_index
from tests.cli_in_process import cli_in_process

def _explain(nouns: list[str], lexicon: dict) -> analogy.Analogy | None:
    return analogy.explain(nouns, lexicon, SHAPE_WORDS, concepts._material_words(), load_lexicon().colors)


def test_wordnet_reads_the_physical_sense() -> None:
    from tasks.geometry.wordnet import wordnet

    puck = wordnet().physical_senses("puck")
    assert puck and "rubber disk" in puck[0].definition  # the hockey puck, not the fairy
    assert wordnet().lemma("mice") == "mouse" and wordnet().lemma("yoga mat") is None
    assert wordnet().physical_senses("zorblat") == []


def test_a_kind_the_lexicon_knows_lends_its_shape() -> None:
    """'spaniel' < sporting dog < hunting dog < dog: with 'dog' in the lexicon, the spaniel is built like it."""
    found = _explain(["spaniel"], {"dog": ("plush_dog", "dog", True)})
    assert found is not None and found.level == "hypernym" and found.concept == "plush_dog"
    assert "dog" in found.chain[-1] and found.chain[0].startswith("WordNet: spaniel")


def test_a_class_gives_a_generic_body_plan() -> None:
    found = _explain(["okapi"], {})  # no lexicon noun on the way up: the class 'mammal'
    assert found is not None and (found.level, found.concept) == ("category", "generic_quadruped")
    found = _explain(["heron"], {})
    assert found is not None and found.concept == "generic_bird"


def test_the_definition_gives_shape_material_and_size() -> None:
    """'puck: a vulcanized rubber disk 3 inches in diameter ...' -> a rubber disc of 7.6 cm."""
    found = _explain(["hockey puck", "puck"], {})
    assert found is not None and found.level == "gloss"
    assert (found.shape_word, found.material_words[:1]) == ("disc", ["rubber"])
    if "puck" not in noun_index() and "hockey puck" not in noun_index():
        d = design_from_text("a hockey puck")
        assert d.concept.fallback_level == "gloss" and d.concept.default_material == "rubber"
        stated = [v for v in (d.size.longest_m, *d.size.extents_m) if v is not None]
        assert max(stated) == pytest.approx(3 * 0.0254) and d.concept.shape_from == "disc"
        assert "WordNet's definition" in (d.size.stated or "")


@pytest.mark.parametrize("text", ["a rubber thingamajig", "a soft gizmo", "a silicone wobbler", "a zorblat",
                                  "a zorblat shaped like a cat", "an exotic fruit", "a four-legged plush glorptail",
                                  "the squishy thing you squeeze", "a foam disc", "something soft and round",
                                  "a plush spaniel-like zorblat", "a rubber grommet", "a tenrec plush"])
def test_no_generic_object_without_the_analogy_message(text: str) -> None:
    """Whatever was built when the lexicon does not name the object, the record says 'by analogy', the warning
    comes first and reads like the one-line note."""
    d = design_from_text(text)
    c = d.concept
    if c.concept.startswith("generic_") or c.fallback_level not in ("exact", "synonym"):
        assert c.by_analogy and c.analogy_line() is not None and c.analogy_line().startswith("built by analogy")
        assert d.warnings and d.warnings[0] == c.fallback_note


def test_every_generic_concept_is_reported_as_an_analogy() -> None:
    """Across the phrase table and made-up nouns: a generic_* concept is never a named match."""
    from tests.geometry.test_phrase_table import TABLE

    texts = [row[0] for row in TABLE] + ["a zorblat", "a plush frumious bandersnatch", "a blob"]
    for text in texts:
        c = design_from_text(text).concept
        if c.concept.startswith("generic_"):
            assert c.by_analogy, text


_cli = cli_in_process


def test_strict_concept_refuses_an_analogy_and_writes_nothing(tmp_path: Path, prefect_api: str,
                                                              monkeypatch: pytest.MonkeyPatch,
                                                              capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "thing"
    code, err = _cli("geometry", "a rubber thingamajig", "--out", str(out), "--no-cache", "--strict-concept",
                     api=prefect_api, monkeypatch=monkeypatch, capsys=capsys)
    assert code == 2, err
    assert err.strip().splitlines()[-1].startswith("error: --strict-concept: built by analogy:")
    assert not out.exists()
    code, err = _cli("generate", "a zorblat", "--out", str(tmp_path / "z"), "--strict-concept", "--no-l3",
                     "--cache", str(tmp_path / "cache"), api=prefect_api, monkeypatch=monkeypatch, capsys=capsys)
    assert code == 2 and "built by analogy" in err and not (tmp_path / "z").exists()


def test_the_first_line_says_built_by_analogy(tmp_path: Path, prefect_api: str, monkeypatch: pytest.MonkeyPatch,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    code, err = _cli("geometry", "a rubber thingamajig", "--out", str(tmp_path / "t"), "--no-cache",
                     api=prefect_api, monkeypatch=monkeypatch, capsys=capsys)
    assert code == 0, err
    assert err.splitlines()[0].startswith("built by analogy: 'thingamajig' is not in the lexicon")
    import json

    concept = json.loads((tmp_path / "t" / "geometry.json").read_text())["info"]["concept"]
    assert concept["fallback_level"] == "material" and concept["default_material"] == "rubber"


def test_the_card_boxes_the_analogy() -> None:
    from tasks.render.card_data import CardData, L3Card
    from tasks.render.card_html import card_html

    card = CardData(name="n", request={"text": "a plush spaniel"}, views={}, drop_frames=[], videos={}, material=[],
                    bands=[], l1=[], protocol=[], l3=L3Card(ran=False, note="no L3"), stages=[], sources=[],
                    built="built: spaniel, by analogy (hypernym)",
                    analogy=["built by analogy: 'spaniel' is not in the lexicon ...", "WordNet: spaniel = '...'"])
    page = card_html(card)
    assert 'class="analogy"' in page and "built by analogy: &#x27;spaniel&#x27;" in page
    named = card_html(card.model_copy(update={"analogy": [], "built": "built: plush dog (named)"}))
    assert 'class="analogy"' not in named


def test_a_word_of_another_sense_lends_nothing() -> None:
    """A washer is 'a seal consisting of a flat disk': the gasket, not the lexicon's plush seal (an animal)."""
    lexicon = {"seal": ("plush_seal", "seal", True)}
    found = analogy.explain(["washer"], lexicon, SHAPE_WORDS, concepts._material_words(), load_lexicon().colors,
                            lambda key: "animal")
    assert found is not None and found.concept != "plush_seal" and found.shape_word == "disc"
    assert concepts.concept_domain("plush_seal") == "animal" and concepts.concept_domain("banana") == "food"


@pytest.mark.parametrize(("first", "noun", "kin"), [
    ("stork", "heron", "wading bird"), ("deer", "camel", "even-toed ungulate"), ("fox", "husky", "canine"),
    ("cat", "kitten", None), ("cow", "calf", None), ("otter", "sea otter", None), ("rabbit", "bunny", None),
    ("trousers", "pants", None),  # listed as the same object (contracts/vocab/wordnet.yaml)
])
def test_a_listed_noun_that_wordnet_files_as_a_sibling_kind_is_kin(first: str, noun: str, kin: str | None) -> None:
    assert analogy.kin_of(first, noun) == kin


def test_a_sibling_kind_listed_under_an_entry_is_built_by_analogy_and_says_so() -> None:
    """'a plush heron' uses the stork's entry (the lexicon lists heron there), but a heron is not a stork: the
    concept is an analogy with its reason, not a named match; a young or a synonym stays named."""
    heron = concepts.read_text("a plush heron").match
    assert heron.concept == "plush_stork" and heron.by_analogy
    assert heron.analogy_line() == ("built by analogy: 'heron' is not in the lexicon: built as its nearest kin there, "
                                    "a stork (both kinds of wading bird in WordNet)")
    assert any("wading bird" in step for step in heron.analogy)
    for text in ("a plush stork", "a kitten plush toy", "a stuffed bunny"):
        assert not concepts.read_text(text).match.by_analogy, text
