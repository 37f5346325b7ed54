"""Misspelt and split words of a request read as the lexicon's own ('slipers' -> 'slippers', 'tooth paste' ->
'toothpaste'): a word no English dictionary (WordNet's four indexes) knows, within one or two letters of exactly one
lexicon word, is read as it; two words that the lexicon writes as one are joined."""

from __future__ import annotations

import difflib
import functools
import re
from collections.abc import Iterable

from tasks.geometry.wordnet import data_dir

MIN_LENGTH = 5  # shorter words are too often another real word one letter away; a word one letter shorter is read
# only as a lexicon word with one letter added or two swapped ('towl': a towel) [-]
MIN_WRONG_LENGTH = 6  # a word read with one letter typed as another at least this long ('eaten' is no 'eater') [-]
MIN_TWO_SLIPS_LENGTH = 6  # a word read with two slips is at least this long ('tounge': a tongue) [-]
CUTOFF = 0.85  # difflib's similarity ratio a correction needs (one letter in 7: 0.93; two in 8: 0.88) [-]
MARGIN = 0.03  # how much nearer the best word must be than the next (else the word is left as written) [-]
# endings an English word takes that WordNet's lemma indexes do not list ('tangled', 'squished', 'bunched', 'eaten')
_ENDINGS = (("ies", "y"), ("ied", "y"), ("es", ""), ("s", ""), ("ed", ""), ("ed", "e"), ("ing", ""), ("ing", "e"),
            ("er", ""), ("est", ""), ("ly", ""), ("y", ""), ("y", "e"), ("ish", ""), ("en", ""), ("en", "e"))
_WORD = re.compile(r"[a-z]+")
# how people type that no dictionary lists ('thats' is no misspelt 'hats')
CASUAL = frozenset("""thats whats dont doesnt didnt cant wont isnt arent wasnt im ive youre theyre lets pls plz gonna
wanna kinda sorta gotta lemme gimme ya yeah okay ok hmm thx thanks approx appx aprox qty pcs pkt pkts incl excl
asst misc""".split())


@functools.lru_cache(maxsize=1)
def english_words() -> frozenset[str]:
    """Every lemma of WordNet's noun, verb, adjective and adverb indexes and their irregular forms (one-word)."""
    words: set[str] = set()
    folder = data_dir()
    for pos in ("noun", "verb", "adj", "adv"):
        with open(folder / f"index.{pos}", encoding="utf-8") as fh:
            words.update(line.split(" ", 1)[0] for line in fh if not line.startswith(" "))
        exceptions = folder / f"{pos}.exc"  # irregular forms ('came', 'threw', 'mice', 'worse'): 'came' was read as a
        if exceptions.exists():  # camel
            with open(exceptions, encoding="utf-8") as fh:
                words.update(line.split(" ", 1)[0] for line in fh if line.strip())
    return frozenset(w for w in words if w.isalpha())


def is_english(word: str) -> bool:
    """True when WordNet knows the word or its stem under a common ending."""
    known = english_words()
    if word in known:
        return True
    return any(word.endswith(end) and word[: -len(end)] + repl in known for end, repl in _ENDINGS
               if len(word) > len(end) + 2 and not (end == "s" and word.endswith("ss")))  # ('octopuss' is no
    # plural: a word in -s takes -es)


def _doubled(word: str) -> str:
    """A word with its doubled last consonant undone before -ed/-ing ('tapped' -> 'tap')."""
    m = re.match(r"^(.*?)([b-df-hj-np-tv-z])\2(ed|ing)$", word)
    return m.group(1) + m.group(2) if m else word


@functools.lru_cache(maxsize=1)
def _function_words() -> frozenset[str]:
    """spaCy's English stop words ('could', 'would', 'every') and the casual spellings: never corrected."""
    from spacy.lang.en.stop_words import STOP_WORDS  # lazy: spaCy's import costs ~1 s, paid by the parse anyway

    return frozenset(STOP_WORDS) | CASUAL


def _one_doubling_away(word: str, vocab: frozenset[str]) -> set[str]:
    """The vocabulary's words that are `word` with one doubled letter single, or one letter doubled."""
    out = {word[:i] + word[i + 1:] for i in range(len(word) - 1) if word[i] == word[i + 1]}
    out |= {word[: i + 1] + word[i] + word[i + 1:] for i in range(len(word))}
    return {w for w in out if w in vocab and w != word}


def _one_swap_away(word: str, vocab: frozenset[str]) -> set[str]:
    """The vocabulary's words that are `word` with two neighbouring letters swapped."""
    out = {word[:i] + word[i + 1] + word[i] + word[i + 2:] for i in range(len(word) - 1)}
    return {w for w in out if w in vocab and w != word}


def _one_letter_short(word: str, vocab: frozenset[str]) -> set[str]:
    """The vocabulary's words that are `word` with one letter added anywhere ('hoodi' -> 'hoodie')."""
    letters = "abcdefghijklmnopqrstuvwxyz"
    out = {word[:i] + c + word[i:] for i in range(len(word) + 1) for c in letters}
    return {w for w in out if w in vocab}


def _one_letter_wrong(word: str, vocab: frozenset[str]) -> set[str]:
    """The vocabulary's words that are `word` with one letter typed as another ('beenie' -> 'beanie')."""
    letters = "abcdefghijklmnopqrstuvwxyz"
    out = {word[:i] + c + word[i + 1:] for i in range(len(word)) for c in letters if c != word[i]}
    return {w for w in out if w in vocab}


def corrections(text: str, vocabulary: Iterable[str], phrases: Iterable[str] = ()) -> list[tuple[str, str]]:
    """(as written, as read) for each misspelt or split word of a normalised text against the lexicon's words;
    two words are joined only when no lexicon noun phrase (`phrases`) holds them as written ('bath mat')."""
    return list(_corrections(text, frozenset(vocabulary), frozenset(phrases)))


@functools.lru_cache(maxsize=1024)
def _corrections(text: str, vocab: frozenset[str], phrases: frozenset[str]) -> tuple[tuple[str, str], ...]:
    """The cached corrections of one text against one vocabulary."""
    words = _WORD.findall(text)
    out: list[tuple[str, str]] = []
    for a, b in zip(words, words[1:], strict=False):  # 'tooth paste' -> 'toothpaste'
        if a + b in vocab and len(a) >= 3 and len(b) >= 3 and not any(f"{a} {b}" in p for p in phrases):
            out.append((f"{a} {b}", a + b))
    for w in dict.fromkeys(words):
        if len(w) < MIN_LENGTH - 1 or w in vocab or w in _function_words() or is_english(w) or is_english(_doubled(w)):
            continue
        if len(w) < MIN_LENGTH:  # a short word only with a letter left out or two typed in turn ('towl': a towel;
            near = _one_letter_short(w, vocab) or _one_swap_away(w, vocab)  # 'bera': a bear)
            if len(near) == 1:
                out.append((w, near.pop()))
            continue
        split = [f"{w[:i]} {w[i:]}" for i in range(3, len(w) - 2) if f"{w[:i]} {w[i:]}" in phrases]
        if len(split) == 1:  # two words written as one ('teddybear', 'rubberband'): the lexicon's noun phrase
            out.append((w, split[0]))
            continue
        doubled = _one_doubling_away(w, vocab)  # the commonest slip first: a letter doubled or not ('bananna' is a
        if len(doubled) == 1:  # banana, though 'bandanna' is as near by difflib's ratio)
            out.append((w, doubled.pop()))
            continue
        swapped = _one_swap_away(w, vocab)  # then two letters typed in turn ('jakcet': difflib's ratio is 0.83)
        if len(swapped) == 1:
            out.append((w, swapped.pop()))
            continue
        short = _one_letter_short(w, vocab)  # then a letter left out ('hoodi': difflib finds 'hood' as near), the
        if len(short) > 1:  # last one first ('blanke' is a blanket before a blankie)
            short = {c for c in short if c.startswith(w)} or short
        if len(short) == 1:
            out.append((w, short.pop()))
            continue
        wrong = _one_letter_wrong(w, vocab) if len(w) >= MIN_WRONG_LENGTH else set()  # then one letter typed as
        if len(wrong) == 1:  # another ('beenie': difflib's ratio 0.83)
            out.append((w, wrong.pop()))
            continue
        close = difflib.get_close_matches(w, vocab, n=2, cutoff=CUTOFF)
        if len(close) == 1 or (len(close) == 2 and difflib.SequenceMatcher(None, w, close[0]).ratio()
                               > difflib.SequenceMatcher(None, w, close[1]).ratio() + MARGIN):
            out.append((w, close[0]))
            continue
        two = _two_slips_away(w, vocab) if len(w) >= MIN_TWO_SLIPS_LENGTH else set()  # last, two slips ('tounge':
        if len(two) == 1:  # a tongue, 'sossages': sausages), only to the one word that starts as it does
            out.append((w, two.pop()))
    return tuple(out)


def _slips(a: str, b: str, limit: int = 2) -> int:
    """Typing slips between two words (optimal string alignment: a letter left out, added, typed as another, or two
    typed in turn), counted up to limit + 1."""
    if abs(len(a) - len(b)) > limit:
        return limit + 1
    prev2: list[int] = []
    prev = list(range(len(b) + 1))
    for i in range(1, len(a) + 1):
        cur = [i] + [0] * len(b)
        for j in range(1, len(b) + 1):
            cost = a[i - 1] != b[j - 1]
            cur[j] = min(prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + cost)
            if i > 1 and j > 1 and a[i - 1] == b[j - 2] and a[i - 2] == b[j - 1]:
                cur[j] = min(cur[j], prev2[j - 2] + 1)
        if min(cur) > limit:
            return limit + 1
        prev2, prev = prev, cur
    return prev[-1]


def _two_slips_away(word: str, vocab: frozenset[str]) -> set[str]:
    """The vocabulary's words at most two slips from `word` that start with its letter (a slip rarely hits the
    first); none when one is a single slip away (that one is already taken above, or there are several)."""
    bones = _consonants(word)
    slips = {v: _slips(word, v) for v in vocab if v[0] == word[0] and abs(len(v) - len(word)) <= 2}
    if any(n <= 1 for n in slips.values()):  # ('beenie' with 'beanie' and 'weenie': a slip two ways, left as is)
        return set()
    return {v for v, n in slips.items() if n <= 2 and _consonants(v) == bones}


def _consonants(word: str) -> str:
    """A word's consonants, doubled ones once: two slips are read only where they keep its sound's frame ('tounge'
    and 'tongue': tng; 'sossages' and 'sausages': ssgs), not where they make another word ('shemagh' is no 'sheath',
    'ballgown' no 'balloon', 'punchbag' no 'punching')."""
    return re.sub(r"(.)\1+", r"\1", re.sub(r"[aeiouy]", "", word))


def corrected(text: str, vocabulary: Iterable[str], phrases: Iterable[str] = ()) -> str:
    """The text with its corrections applied (whole words only)."""
    for wrong, right in corrections(text, vocabulary, phrases):
        text = re.sub(rf"\b{re.escape(wrong)}\b", right, text)
    return text


__all__ = ["corrected", "corrections", "english_words", "is_english"]
