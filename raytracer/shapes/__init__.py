"""Shapes (chapters 5, 6, 9 and later): the abstract ``Shape`` and one module per kind.

Import from the modules (``raytracer.shapes.sphere``) or from ``raytracer`` itself. A shape's
conversions between world and object space are ``raytracer.space``'s (patterns and
materials use them too, below the shapes).
"""
