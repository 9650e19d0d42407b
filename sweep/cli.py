"""The command line: ``python -m sweep run|plan|status|collect|figures``.

This is the only place that reads ``MPI.COMM_WORLD``, and only for ``run``; the other
commands are serial and do not initialise MPI.  Launch parallel runs as
``mpiexec -n N python -m mpi4py -m sweep run JOB.toml`` so that an uncaught exception
aborts every rank.

Exit status: 0 success (every task ok or not converged), 1 the run was refused or could
not finish (files missing or unwritable, output in use), 2 the job file or the command line
is invalid, 3 the run finished and wrote its result but some tasks failed (their status
and message are in the file).  Messages go to stderr, from rank 0.
"""

import sweep.threads  # noqa: F401  (before numpy and numba load: one thread per rank)

import argparse
import gc
import os
import sys
from pathlib import Path

from sweep import analyses, progress, provenance
from sweep.analyses.base import JobError
from sweep.analyses.mode_sets import ModeSetSweep
from sweep.errors import RunError
from sweep.jobspec import Job, load_job, parse_job, read_job_text

EXIT_FAILED = 1
EXIT_INVALID = 2
EXIT_TASKS_FAILED = 3
EXIT_INTERRUPTED = 130


def _error(message: str, details: str = "") -> None:
    sys.stderr.write(details)
    print(f"error: {message}", file=sys.stderr)


def _job_error(path, exc: JobError) -> None:
    """One ``error:`` line per problem of a job file."""
    for line in str(exc).splitlines():
        _error(f"{path}: {line}")


def _output(args: argparse.Namespace, job: Job) -> Path:
    return Path(args.output) if args.output else Path(f"{job.name}.nc")


def _run(args: argparse.Namespace) -> int:
    from mpi4py import MPI

    comm = MPI.COMM_WORLD
    try:
        code = _run_on(comm, args)
    except KeyboardInterrupt:
        # Every rank gets the signal; the runner released the lock on its way out.  Leave
        # without MPI_Abort's notice and without a traceback.
        if comm.rank == 0:
            where = f"{args.output}.parts/" if args.output else "the parts directory of the output"
            print(f"\ninterrupted: the finished chunks are kept in {where}; run the same command with "
                  "--resume to continue", file=sys.stderr)
            sys.stderr.flush()
        os._exit(EXIT_INTERRUPTED)
    except (JobError, RunError) as exc:
        if comm.rank == 0:
            if isinstance(exc, JobError):
                _job_error(args.job, exc)
            else:
                _error(exc.message, exc.details)
            sys.stderr.flush()
        code = EXIT_INVALID if isinstance(exc, JobError) else EXIT_FAILED
    # Every rank reaches this point with the same outcome, after rank 0 has printed.
    comm.Barrier()
    if code and comm.size > 1:
        # Under ``python -m mpi4py`` a non-zero exit calls MPI_Abort, which tears the job
        # down while rank 0's message may still be in the launcher's output pipes; the
        # failure is agreed, so finalize cleanly and keep the exit status.
        MPI.Finalize()
    return code


def _run_on(comm, args: argparse.Namespace) -> int:
    """``run``; collective over comm.  Raises the same error on every rank."""
    from sweep import runner

    read = None
    if comm.rank == 0:
        try:
            read = ("ok", read_job_text(args.job))
        except JobError as exc:
            read = ("error", (exc.key, exc.value, exc.allowed))
    kind, value = comm.bcast(read, root=0)
    if kind == "error":
        raise JobError(*value)
    job = parse_job(value, args.job)
    stream, bar = progress.open_stream(args.progress) if comm.rank == 0 else (None, False)
    try:
        summary = runner.run(job, _output(args, job), comm, resume=args.resume, overwrite=args.overwrite,
                             allow_code_change=args.allow_code_change, break_lock=args.break_lock,
                             piece=args.chunks, progress_stream=stream, progress_bar=bar)
    finally:
        if stream is not None and stream is not sys.stderr:
            stream.close()
    report = summary.report
    if report is None:
        if comm.rank == 0:
            for note in summary.notes:
                print(f"note: {note}", file=sys.stderr)
            i, n = args.chunks
            print(f"piece {i}/{n} of {_output(args, job)}: {summary.tasks_computed} tasks computed "
                  f"({summary.tasks_failed} failed) on {comm.size} rank(s) in {summary.seconds:.2f} s; when "
                  f"every piece has run: python -m sweep collect {_output(args, job)}")
        return EXIT_TASKS_FAILED if summary.tasks_failed else 0
    if comm.rank == 0:
        for note in summary.notes + report.notes:
            print(f"note: {note}", file=sys.stderr)
        if args.report_memory:
            ranks = ", ".join(f"{m:.1f}" for m in summary.peak_rss_mib)
            print(f"memory: peak RSS per rank after compute (MiB): {ranks}; rank 0 after "
                  f"collect: {summary.peak_rss_collect_mib:.1f}", file=sys.stderr)
        print(f"wrote {report.path}: {report.summary()}; {summary.tasks_computed} computed by this run "
              f"on {comm.size} rank(s) in {summary.seconds:.2f} s")
    return EXIT_TASKS_FAILED if report.failed else 0


def _plan(args: argparse.Namespace) -> int:
    job = load_job(args.job)
    layout = job.layout
    print(f"job {job.name!r}, analysis {job.analysis_name!r}, from {args.job}")
    for dim, values in zip(layout.dims, layout.values):
        print(f"  {dim}: {len(values)} value(s) from {values[0]:g} to {values[-1]:g}")
    if isinstance(job.analysis, ModeSetSweep):
        print(f"  mode_set: {len(job.options.labels)} mode set(s), {', '.join(job.options.labels)} "
              f"({job.options.n_inner} subtask(s) each)")
    print(f"grid shape {layout.shape} (dims {', '.join(layout.dims)}), "
          f"{layout.n_subtasks} subtask(s) per grid point")
    last = len(layout.chunk_tasks(layout.n_chunks - 1))
    print(f"tasks: {layout.n_tasks} in {layout.n_chunks} chunk(s) of {layout.chunk} "
          f"task(s) (the last holds {last})")
    print(f"output: {_output(args, job)}")
    return 0


def _status(args: argparse.Namespace) -> int:
    from sweep.storage.status import describe_status

    print(describe_status(Path(args.out)))
    return 0


def _collect(args: argparse.Namespace) -> int:
    from sweep.storage.netcdf import collect

    report = collect(Path(args.out), break_lock=args.break_lock)
    for note in report.notes:
        print(f"note: {note}", file=sys.stderr)
    print(f"wrote {report.path}: {report.summary()}")
    return EXIT_TASKS_FAILED if report.failed else 0


def _export(args: argparse.Namespace) -> int:
    from sweep.export import export_fe

    for path in export_fe(args.job, args.output):
        print(f"wrote {path}")
    return 0


def _figures(args: argparse.Namespace) -> int:
    import matplotlib

    matplotlib.use("Agg")  # a command-line tool: files only
    import xarray as xr

    from sweep import figures

    loaded = []
    for name in args.out:
        out = Path(name)
        if not out.exists():
            raise RunError(f"{out} does not exist")
        try:
            ds = xr.load_dataset(out, engine="netcdf4")
        except (OSError, ValueError) as exc:
            raise RunError(f"{out} is not a readable NetCDF result ({type(exc).__name__}); give the "
                           "output file of a run (OUT.nc), not a job file") from None
        if "analysis" not in ds.attrs:
            raise RunError(f"{out} is not a membrane-sweep result (no analysis attribute)")
        loaded.append(ds)
    kinds = {ds.attrs["analysis"] for ds in loaded}
    if len(kinds) > 1:
        raise RunError(f"results of different analyses ({', '.join(sorted(kinds))}) cannot be drawn together")
    analysis = analyses.get(loaded[0].attrs["analysis"])
    options = dict(fmt=args.format, dpi=args.dpi, style=args.style)
    try:
        # several results: each in a directory of its own (their figures share names)
        stems = [Path(name).stem for name in args.out]
        if len(loaded) > 1 and len(set(stems)) < len(stems):  # a/out.nc and b/out.nc
            stems = [f"{k}-{stem}" for k, stem in enumerate(stems, 1)]
        dirs = [Path(args.output) / stem if len(loaded) > 1 else Path(args.output) for stem in stems]
        paths = [p for ds, where in zip(loaded, dirs) for p in figures.draw(analysis, ds, where, **options)]
        if len(loaded) > 1:
            together = figures.draw_comparison(analysis, loaded, Path(args.output), **options)
            if not together:
                print(f"analysis {analysis.name!r} has no figures of several results together")
            paths += together
    except OSError as exc:
        raise RunError(f"cannot use the style {args.style!r} or write to {args.output}: {exc}") from None
    if not paths:
        print(f"analysis {analysis.name!r} has no figures")
    for path in paths:
        print(path)
    return 0


def _piece(text: str) -> tuple[int, int]:
    """``"2/8"`` -> ``(2, 8)`` for ``run --chunks``."""
    try:
        i, n = (int(v) for v in text.split("/"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is invalid: give I/N, two integers, 1 <= I <= N") from None
    if not 1 <= i <= n:
        raise argparse.ArgumentTypeError(f"{text!r} is invalid: need 1 <= I <= N")
    return i, n


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``python -m sweep``."""
    parser = argparse.ArgumentParser(
        prog="python -m sweep",
        description="Parameter sweeps of the pre-stretched hyperelastic annular membrane.",
        epilog="Parallel: mpiexec -n N python -m mpi4py -m sweep run JOB.toml")
    parser.add_argument("--version", action="version",
                        version=f"membrane-sweep {provenance.package_version()}")
    commands = parser.add_subparsers(dest="command", required=True)

    run = commands.add_parser("run", help="validate, compute under MPI, write the NetCDF")
    run.add_argument("job", help="job file (TOML)")
    run.add_argument("-o", "--output", help="output NetCDF (default: <job name>.nc)")
    again = run.add_mutually_exclusive_group()
    again.add_argument("--resume", action="store_true",
                       help="compute only the chunks missing from OUT.nc.parts/")
    again.add_argument("--overwrite", action="store_true",
                       help="delete OUT.nc and OUT.nc.parts/ first")
    run.add_argument("--allow-code-change", action="store_true",
                     help="resume although the code differs from the earlier runs' (recorded in the result)")
    run.add_argument("--break-lock", action="store_true",
                     help="remove the lock of a run that no longer exists on another host")
    run.add_argument("--chunks", type=_piece, metavar="I/N",
                     help="compute piece I of N of the job (every N-th chunk; a Slurm array task); "
                          "implies --resume; 'collect' merges the pieces")
    run.add_argument("--report-memory", action="store_true",
                     help="print the peak resident memory of each rank")
    run.add_argument("--progress", choices=progress.MODES, default="auto",
                     help="progress of rank 0: a bar redrawn on the terminal (also under mpiexec), "
                          "plain lines (logs), or none; auto: a bar on a terminal, lines otherwise")
    run.set_defaults(handler=_run)

    plan = commands.add_parser("plan", help="validate and print the task layout")
    plan.add_argument("job", help="job file (TOML)")
    plan.add_argument("-o", "--output", help="output NetCDF (default: <job name>.nc)")
    plan.set_defaults(handler=_plan)

    status = commands.add_parser("status", help="completed / total tasks of a run")
    status.add_argument("out", help="output NetCDF of the run")
    status.set_defaults(handler=_status)

    collect = commands.add_parser("collect", help="merge the finished parts into the NetCDF")
    collect.add_argument("out", help="output NetCDF of the run")
    collect.add_argument("--break-lock", action="store_true",
                         help="remove the lock of a run that no longer exists on another host")
    collect.set_defaults(handler=_collect)

    figures = commands.add_parser("figures", help="standard plots of a result (PNG, PDF or SVG); of several "
                                                  "results of one analysis, also their comparison")
    figures.add_argument("out", nargs="+", help="NetCDF result(s); several: each drawn, and together where the "
                                                "analysis compares (backbones across models), each result's own "
                                                "figures then in OUTPUT/<file stem>/")
    figures.add_argument("-o", "--output", default="figures",
                         help="directory for the figure files (default: figures)")
    figures.add_argument("--format", choices=("png", "pdf", "svg"), default="png",
                         help="file format (default png; pdf and svg are vector)")
    figures.add_argument("--dpi", type=float, help="resolution of raster output (default 120; basins 150)")
    figures.add_argument("--style", help="a matplotlib style name or .mplstyle file, on top of the house style")
    figures.set_defaults(handler=_figures)

    export = commands.add_parser("export", help="the 2-D FE check's mesh, pre-stretch and mode shapes as .vtu "
                                                "files (ParaView), one per grid point of a linear fe2d job")
    export.add_argument("job", help="job file (TOML): analysis linear, [model] kind = \"fe2d\"")
    export.add_argument("-o", "--output", default="export", help="directory for the files (default: export)")
    export.set_defaults(handler=_export)
    return parser


def exit_main() -> None:
    """Run :func:`main` and exit with its status: ``python -m sweep`` and ``membrane-sweep``.

    Before the interpreter exits, every object still alive is moved out of the garbage
    collector's reach (:func:`gc.freeze`), so that the interpreter's final collections
    skip numba's compiled code and everything else a command loaded: 0.2-0.25 s of every
    command's exit on this machine (with the kernels of a basins job loaded; every file
    is closed by then).
    """
    status = main()
    gc.freeze()
    raise SystemExit(status)


def main(argv: list[str] | None = None) -> int:
    """The command line: ``python -m sweep`` and ``membrane-sweep`` (through :func:`exit_main`).

    Parameters
    ----------
    argv : list of str, optional
        Arguments (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        Exit status: 0, :data:`EXIT_FAILED`, :data:`EXIT_INVALID` or :data:`EXIT_TASKS_FAILED`.
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    if getattr(args, "chunks", None) and args.overwrite:
        parser.error("--chunks cannot be combined with --overwrite (pieces add to one output; delete it first)")
    try:
        return args.handler(args)
    except KeyboardInterrupt:
        print("\ninterrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except JobError as exc:
        _job_error(getattr(args, "job", None) or args.out, exc)
        return EXIT_INVALID
    except RunError as exc:
        _error(exc.message, exc.details)
        return EXIT_FAILED
