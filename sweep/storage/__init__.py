"""Result storage: append-only part logs per rank and run, merged into one NetCDF file.

Layout next to the output ``OUT.nc``::

    OUT.nc.parts/manifest.json                the job file text and its SHA-256, the chunk layout
    OUT.nc.parts/run-0002.json                run 2: start, host, ranks, chunks, provenance
    OUT.nc.parts/lock                         held by the run or collect writing (host, pid, start);
                                              lock-piece-1-of-4 by a run of one piece
    OUT.nc.parts/run-0002-rank-00001.log      the chunks rank 1 computed in run 2
                                              (:mod:`sweep.partlog`: checksummed records)

A run appends one record per finished chunk to its rank's log, so a sweep leaves a few
files per rank whatever its task count, and a killed rank loses at most the chunk it was
writing.  Every record is verified when read (checksum, task range); a record that fails
is reported by file and offset, never merged, and its chunk is computed again by
``--resume``.  The logs are kept after a successful collect: collecting again gives
the same file, ``--resume`` finds nothing to do, ``status`` reads them.

One writer per output: a lock (an ``O_EXCL`` file, safe on NFS and Lustre) is held
by a run, or by ``collect``, for as long as it writes; a second one is refused at once
with the holder's host, process and start time.  A job split into pieces (``run --chunks
I/N``, a Slurm array) runs its pieces at once, each holding the lock of its own piece and
computing every N-th chunk; ``collect`` merges them when all are done.  Run numbers are
allocated by creating ``run-RRRR.json`` with ``O_EXCL``, so concurrent pieces never share
one.

A collect streams: results whose published layout is the raw one (every analysis
but ``basins``) are written window by window of consecutive tasks straight into the
NetCDF file, so rank 0's memory does not grow with the task count.  An analysis with its
own ``assemble`` (basins: tiles into lattices) is merged in memory.

The merged file is identical whatever the rank count and the order in which chunks
finished: values are placed by task index.  Its attributes ``date_created`` and
``history`` change from one collect to the next.

The modules, one concept each:

* :mod:`sweep.storage.parts`: the parts directory (paths, manifest, run records, logs);
* :mod:`sweep.storage.lock`: one writer per output;
* :mod:`sweep.storage.resume`: preparing a run (what is done, what to compute);
* :mod:`sweep.storage.netcdf`: the merge into NetCDF and the run attributes of a result;
* :mod:`sweep.storage.status`: the ``status`` command's report;
* :mod:`sweep.storage.tally`: tasks counted by status;
* :mod:`sweep.storage.files`: one-line file-system errors, atomic replacement.
"""
