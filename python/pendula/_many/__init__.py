"""The many-state machinery (private): every path that answers many pendulums per call.

- ``kernels``: the Fortran batch kernels (RK4, CVODE) over a broadcast batch;
- ``pool``: one scalar call per state on a thread pool (scenes, CVODE events);
- ``ensemble``: the batch path of ``pendula.rk4`` / ``pendula.cvode`` and
  ``BatchIntegrationResult``;
- ``scenes``: ``SceneBatch`` and its solves (the one-scene solve handed in).

It builds on the package's base (``_arrays``, ``_errors``, ``_defaults``,
``_longcall``, ``_tables``) and never imports the public modules above it
(``integrate``, ``scene``, ``sweep``), which import it: imports run one way
(docs/contributing.md).
"""
