"""The step library: the book's Given/When/Then notation evaluated against a variant's API.

- ``notation``: book text (``√2/2``, ``2:A``, ``from``, ``the first object in w``) -> Python
  source.
- ``evaluator``: a safe, allow-listed ``ast`` walker; API names win in call position.
- ``compare``: the book's approximate equality (EPSILON) and readable descriptions.
- ``book``: one scenario's namespace; dotted assignment, frozen values replaced.
- ``phrases``: the ordered Given/When and Then step forms.
- ``plugin``: the pytest plugin (``--variant``, ``variant`` and ``book`` fixtures, steps).
- ``kata``: runs a folder of feature files and reports chapter by chapter (``rtc kata``).
"""
