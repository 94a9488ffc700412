# SPDX-License-Identifier: GPL-3.0-or-later
"""The live simulations by object name (entries are sim.session.LiveSim). A leaf: the
settings and the models read an object's entry here without importing the session."""

_entries = {}  # object name -> LiveSim


def get(name):
    return _entries.get(name)


def names():
    return list(_entries)
