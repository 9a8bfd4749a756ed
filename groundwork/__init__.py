"""The ground floor: what every layer above the book's reference uses, importing nothing of
the project but the book's canvas (``raytracer.canvas``, to write it as an image).

Modules: ``files`` (reading a file a user names, within a bound; writing a file
atomically), ``sizes`` (a canvas size and its one parser), ``memory`` (refusing work that
cannot fit before it starts), ``progress`` (bars and plain lines on stderr for a long job),
``images`` (canvases written as PNG or PPM, PNGs read back), ``escapes`` (text quoted from
a user's file shown with its control characters escaped), ``knobs`` (numba's environment
variables checked before numba reads them).
"""
