# SPDX-License-Identifier: GPL-3.0-or-later
"""What a settings change asks of the rest of the add-on, without the settings importing
it: a property's update calls changed(obj, topic); the feature that answers a topic
(the live session, the material) listens to it from its register().

Topics:
  "params"         a setting the running simulation takes at once (parameters)
  "fields"         the Fields image or attributes
  "maps"           a parameter map or stimulus slot
  "show_fields"    the Show Fields overlay of the material
  "display_range"  what the top of the colour ramp means (the model's Display Range)

Imports nothing; registers nothing itself.
"""

TOPICS = ("params", "fields", "maps", "show_fields", "display_range")

_listeners = {topic: [] for topic in TOPICS}


def listen(topic, function):
    """Calls function(obj) on every changed(obj, topic) until forget()."""
    if function not in _listeners[topic]:
        _listeners[topic].append(function)


def forget(topic, function):
    if function in _listeners[topic]:
        _listeners[topic].remove(function)


def changed(obj, topic):
    """Tells the listeners of topic that obj's settings changed (nothing happens while
    no feature listens, e.g. between unregister and register)."""
    for function in list(_listeners[topic]):
        function(obj)
