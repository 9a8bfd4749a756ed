"""The step library: the book's Given/When/Then notation evaluated against a variant's API."""
