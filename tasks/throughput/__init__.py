"""The throughput benchmark of the real job as data (`deformsmith bench throughput`, run by flows.throughput over
flows.batch): the background samplers (GPUs through nvidia-smi, the workers' memory from /proc), the run on disk that
a killed run resumes from (ledger), and the report with its figures (report)."""
