"""Snakemake script: the traces of the design a study's pages show (after the merge: the best
design is a question asked of the whole result), by the study's own traces function."""

from clutchlab import store, traces

sm = snakemake  # noqa: F821
with store.open(sm.input[0]) as lazy:  # only the columns the choice of design needs
    ds = lazy[traces.needed(lazy)].load()
    ds.attrs = dict(lazy.attrs)
out = traces.compute(ds, dict(sm.params.options))
out.attrs.update(
    {
        k: ds.attrs[k]
        for k in (
            "study",
            "config",
            "clutchlab_version",
            "clutchlab_source",
            "clutchlab_design_hash",
        )
        if k in ds.attrs
    }
)
store.write(out, sm.output[0], with_checksum=True)
