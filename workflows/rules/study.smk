# Generic study rules: design -> K chunk jobs -> merge (one HDF5 file per job, never shared).


rule design:
    input:
        lambda wc: [refine_source(wc.study)] if wc.study in REFINED else [],
    output:
        f"{WORK}/{{study}}/design.h5",
    benchmark:
        f"{WORK}/{{study}}/benchmark/design.tsv"
    log:
        f"{WORK}/{{study}}/log/design.log",
    priority: _cluster.DESIGN_PRIORITY  # (the chunks wait for it: every design first)
    params:
        study=lambda wc: RESOLVED[wc.study],
        source=SOURCE,
    resources:
        runtime=10,
        mem_mb=2000,
    script:
        "../scripts/design.py"


rule chunk:
    input:
        f"{WORK}/{{study}}/design.h5",
    output:
        f"{WORK}/{{study}}/chunk_{{i}}.h5",
    benchmark:
        f"{WORK}/{{study}}/benchmark/chunk_{{i}}.tsv"  # wall time and peak RSS of the job
    log:
        f"{WORK}/{{study}}/log/chunk_{{i}}.log",  # progress: scenarios done, rate, time left
    # before the jobs that call the kernels outside a study (numerics, hard cases, benchmark):
    # a chunk compiles each kernel it needs once (pipeline.run_chunk), and they load it; each
    # study's first chunk before the other chunks, so that the studies' kernels compile side by
    # side (a study's second chunk would wait for its first one's compile under its lock); among
    # equals the longest study first
    priority: lambda wc: _cluster.chunk_priority(RESOLVED, wc.study, wc.i)
    params:
        options=lambda wc: RESOLVED[wc.study]["options"],
        chunks=lambda wc: RESOLVED[wc.study]["chunks"],
        source=SOURCE,
    resources:  # from the chunk's scenarios and the study's measured cost (clutchlab.cluster)
        mem_mb=lambda wc: _cluster.chunk_resources(RESOLVED[wc.study])["mem_mb"],
        runtime=lambda wc: _cluster.chunk_resources(RESOLVED[wc.study])["runtime"],
        cpus_per_task=1,
    script:
        "../scripts/chunk.py"


for _study in STUDIES:

    rule:
        # the merged result; then, in the same job (one start-up fewer a study), its design
        # answers, sensitivity indices, robust answers and the traces of the design the study's
        # pages show (clutchlab.traces: the best design is only known once the chunks are merged)
        name:
            f"merge_{_study}"
        input:
            design=f"{WORK}/{_study}/design.h5",
            chunks=chunk_files(_study),
        output:
            results(_study),
            sensitivity_files(_study),
            robust_files(_study),
            traces_files(_study),
        benchmark:
            f"{WORK}/{_study}/benchmark/merge.tsv"
        log:
            f"{WORK}/{_study}/log/merge.log",
        params:
            objectives=RESOLVED[_study]["objectives"],
            constraints=RESOLVED[_study]["constraints"],
            options=RESOLVED[_study]["options"],  # (the traces')
            config=study_config(_study),  # each chunk and the design must come from it
            source=SOURCE,
        resources:
            **_cluster.merge_resources(RESOLVED[_study]),
        script:
            "../scripts/merge.py"


if VALIDATED:

    rule validation:
        # the published numbers every validated study reproduces: one job (each takes a moment)
        output:
            [f"{RESULTS}/{s}/validation.h5" for s in VALIDATED],
        benchmark:
            f"{WORK}/benchmark/validation.tsv"
        log:
            f"{WORK}/log/validation.log",
        params:
            studies=VALIDATED,
            source=SOURCE,
        resources:
            runtime=5,
            mem_mb=1000,
        script:
            "../scripts/validation.py"
