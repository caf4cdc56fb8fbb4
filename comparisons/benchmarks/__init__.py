"""Measurements and calibrations run by hand, each a subcommand of ``python -m comparisons``.

* :mod:`.against_pymunk` (``against-pymunk``): wall time and error of the native core against pymunk;
* :mod:`.scaling` (``scaling``): cost of the native core as scenes grow;
* :mod:`.sweep_throughput` (``sweep-throughput``): runs per minute of a parameter sweep;
* :mod:`.stability_probe` (``stability-probe``): the estimated stability limit against the real one;
* :mod:`.calibrate_damping` (``calibrate-damping``): the contact damping that matches Housner's impact loss;
* :mod:`.stiffness_ensembles` (``stiffness-ensembles``): whether multi-block answers depend on K_n;
* :mod:`.column_ensemble` (``column-ensemble``): the 8-drum column's ensemble, Moreau-Jean against the peers;
* :mod:`.batch_throughput` (``batch-throughput``): member-runs per second of ``simulate_batch``;
* :mod:`.overturn_rule` (``overturn-rule``): whether blocks that pass their critical angle come back;
* :mod:`.moreau_stages` (``moreau-stages``): where Moreau-Jean's step spends its time;
* :mod:`.gpu_check` (``gpu-check``): the GPU path measured on the machine it runs on;
* :mod:`.gpu_reference` (``gpu-reference``): the device check's CPU side, run ahead where there is no GPU;
* :mod:`.kernel_accesses` (``kernel-accesses``): a GPU thread's reads and writes a step, counted without a GPU;
* :mod:`.step_instructions` (``step-instructions``): a member's step in instructions, counted on the CPU, and what
  that many allows a GPU.
"""
