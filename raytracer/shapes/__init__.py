"""Shapes (chapters 5, 6, 9 and later): the abstract ``Shape`` and one module per kind.

Import from the modules (``raytracer.shapes.sphere``) or from ``raytracer`` itself. This
package file stays empty so that ``raytracer.shapes.space`` can be imported without pulling
in shapes, materials and patterns (which need it).
"""
