"""The built-in virtual-system types, one module each.

Every module here defines ``TYPE``, a :class:`~impedance_mil.virtual.registry.VSType`
(its :class:`~impedance_mil.virtual.definition.VSDefinition`, design targets and
presets) and ``ORDER``, its place in listings.  :mod:`impedance_mil.virtual.registry`
finds them; adding a type is adding a module (and its tests).
"""
