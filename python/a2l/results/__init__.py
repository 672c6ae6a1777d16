"""``a2l results``: the published tables, regenerated from one command on one commit.

- :mod:`~a2l.results.catalog`: the named experiments behind the tables, per profile;
- :mod:`~a2l.results.run`: run them, write ``docs/results/``, copy the tables into the
  README's and the docs' marked blocks;
- :mod:`~a2l.results.blocks`: the marked blocks (``<!-- results:NAME -->``);
- :mod:`~a2l.results.provenance`: commit, clean tree, machine, date.
"""
