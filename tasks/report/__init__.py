"""What the command line shows of results: rich tables and one-line texts built from records and reports (the
commands in flows/cli print them), and the parsing of option values. Light at import: no numpy, no Prefect, so that
`deformsmith --help` stays quick."""
