"""Mutation fuzzing of the front end: every input ends in OK or a located error, never a crash.

Inputs are real specs (the ASMETA corpus when it is present, the project's own
specs otherwise) with one or two token-level mutations: a token deleted,
duplicated, swapped with its neighbour, or replaced by another token.  The
random generator is seeded, so the same 2,000+ inputs run every time.
"""
import random
import re
from pathlib import Path

import pytest

from asmcheck.errors import AsmError
from asmcheck.semantics.resolve import check_file

from conftest import ASMETA, ROOT

pytestmark = pytest.mark.engines("none")

TOKEN = re.compile(r'/[^\s"(]+|"[^"\n]*"|\$?[A-Za-z_][A-Za-z0-9_]*|\d+(?:\.\d+)?n?|:=|<-|->|<=|>=|!=|<<|>>|\S')
EXTRA = ["(", ")", "[", "]", "{", "}", ",", ":", ":=", "=", "if", "then", "endif", "par", "endpar", "seq",
         "endseq", "choose", "forall", "do", "with", "in", "undef", "$x", "r_x", "AA", "Dom", "f", "1", "2n",
         "3.5", '"s"', "'c'", "not", "and", "+", "-", "*", "<", ">", "switch", "case", "endswitch", "let",
         "endlet", "extend", "import", "signature", "definitions", "main", "rule", "init", "default"]
N_INPUTS = 2200


def _seeds():
    files = []
    if (ASMETA / "MANIFEST.tsv").exists():
        for line in (ASMETA / "MANIFEST.tsv").read_text().splitlines()[1:]:
            path, verdict = line.split("\t")
            p = ASMETA / path
            if verdict == "accepts" and p.stat().st_size < 2500:
                files.append(p)
    files += sorted((ROOT / "specs").rglob("*.asm"))
    return files


def _mutate(tokens, rng):
    toks = list(tokens)
    for _ in range(rng.choice((1, 1, 2))):
        if not toks:
            break
        i = rng.randrange(len(toks))
        op = rng.randrange(4)
        if op == 0:
            del toks[i]
        elif op == 1:
            toks.insert(i, toks[i])
        elif op == 2 and i + 1 < len(toks):
            toks[i], toks[i + 1] = toks[i + 1], toks[i]
        else:
            toks[i] = rng.choice(EXTRA)
    return toks


def test_fuzz_front_end(tmp_path):
    seeds = _seeds()
    if not seeds:
        pytest.skip("no seed specs (neither the ASMETA corpus nor specs/ is present)")
    rng = random.Random(20261121)
    seen_ok = seen_err = 0
    for n in range(N_INPUTS):
        src = seeds[n % len(seeds)]
        text = src.read_bytes().decode("latin-1")
        # imports made absolute, so the mutated copy can live in a temporary folder
        text = re.sub(r"(?m)^(\s*import\s+)([^\s\"(]+)",
                      lambda m: m.group(1) + str((src.parent / m.group(2)).resolve()), text)
        text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
        text = re.sub(r"//[^\n]*", "", text)
        tokens = []
        for line in text.split("\n"):
            tokens.extend(m.group() for m in TOKEN.finditer(line))
            tokens.append("\n")
        mutated = _mutate(tokens, rng)
        body = " ".join(mutated).replace(" \n ", "\n").replace("\n ", "\n")
        out = tmp_path / f"{n}"
        out.mkdir()
        target = out / f"{src.stem}.asm"
        target.write_text(body, encoding="latin-1")
        try:
            check_file(str(target))
            seen_ok += 1
        except AsmError as err:
            assert err.span is not None and err.span.line >= 1 and err.span.col >= 1, (src, body, err)
            err.render()
            seen_err += 1
    assert seen_ok + seen_err == N_INPUTS
    print(f"fuzz: {seen_ok} accepted, {seen_err} rejected with a located error")
    assert seen_err > N_INPUTS // 4 and seen_ok > N_INPUTS // 20
