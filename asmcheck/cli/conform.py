"""``asmcheck conform``: check a transcript of ASMETA's simulator against the spec."""
from __future__ import annotations

from .. import api
from .common import EXIT_OK, EXIT_VIOLATED, add_domain_options, load_options, out


def run(args) -> int:
    model = api.load(args.file, default_properties=False, **load_options(args))
    tr, res = model.conform(args.transcript)
    if res is None:
        out(f"{args.transcript}: conforms ({len(tr.steps)} step(s) checked"
            + (", ending on an inconsistent update" if tr.stop == "clash" else "") + ")")
        return EXIT_OK
    where = f"{args.transcript}:{res.line}" if res.line else args.transcript
    out(f"{where}: step {res.step} does not conform: {res.reason}")
    if res.location:
        out(f"  the transcript shows   {res.location}={res.expected}")
        out(f"  asmcheck allows        {res.location}=" + (" | ".join(res.allowed) if res.allowed else "(nothing)"))
    return EXIT_VIOLATED


def register(sub) -> None:
    p = sub.add_parser("conform", help="check a transcript of ASMETA's simulator against asmcheck",
                       description="Check that every step of an AsmetaS transcript (java -jar AsmetaS.jar -n N -rnd "
                                   "FILE) is a step asmcheck allows. Exit 0 when it conforms, 1 at the first step "
                                   "that does not, 2 on an input error.")
    p.add_argument("file", metavar="FILE.asm")
    p.add_argument("transcript", metavar="TRANSCRIPT")
    add_domain_options(p)
    p.set_defaults(func=run)
