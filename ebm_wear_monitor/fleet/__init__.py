"""Fleet PHM pipeline on Dask.

Discovery, incremental manifest, per-unit replay tasks, Parquet tables, report, synthetic fleets.
"""
