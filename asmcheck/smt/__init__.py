"""The Z3 engine: bounded model checking and k-induction (the only package that imports z3).

* :mod:`.sym`    guarded unions of concrete values, the symbolic values of the encoding;
* :mod:`.encode` the IR's step as a transition relation over one variable per location;
* :mod:`.bmc`    bounded model checking, k-induction, decoding and replay of traces;
* :mod:`.check`  the entry point used by the API (``Model.bmc``);
* :mod:`.differential` the first violation depths of both engines, for differential tests.
"""
