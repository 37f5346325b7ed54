"""Evaluation: suites of cases, the paper's ablations (Table III), metrics, aggregation and the report."""
