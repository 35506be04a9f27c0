"""stampc.semantics: loading (``use``, problem → domain), name resolution, type checks
and lints; the Python API is in ``stampc.semantics.api`` (``parse``, ``load``, ``check``)."""
