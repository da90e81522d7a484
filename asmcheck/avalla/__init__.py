"""Avalla scenarios: ASMETA's scenario language (AsmetaV), read and run by asmcheck."""
