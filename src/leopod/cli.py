"""The ``leopod`` command: write, check and run a campaign, build its report (over Snakemake).

::

    leopod init NAME --satellite SAT --start YYYY-MM-DD --end YYYY-MM-DD [--system G]
                [--products cod] [--directory D] [--force]
                                              NAME.yaml in D: a commented campaign with every
                                              input as download:<family> of the catalogue and
                                              the satellite's facts from config/satellites.yaml
                                              (leopod.workflow.init)
    leopod check CAMPAIGN [--directory D]     the campaign against the schema (one line per
                                              problem, did-you-mean for misspelt keys) and the
                                              input files it names, per entry and day
    leopod run CAMPAIGN [--directory D] [--cores N] [--profile P] [--exclude-failed]
                        [--progress on|off|auto] [-- SNAKEMAKE OPTIONS]   (``-- -n``: dry run)
                                              with progress (default: on a terminal) one line
                                              per started and finished job, jobs done / total,
                                              errors; Snakemake's whole log stays in
                                              .snakemake/log/ (leopod.workflow.progress)
                                              with --exclude-failed: keep going past failed
                                              jobs, then leave the days with a failed job out
                                              (results/<campaign>/failed_days.yaml: config
                                              exclude_days,
                                              exclude_pod_days) and run again, so that the
                                              other days and the summary finish; the failed
                                              days are listed
    leopod status CAMPAIGN [--directory D]    the days with an orbit and the failed jobs of a
                                              run, each failed day with its reason (the error
                                              in its log)
    leopod report CAMPAIGN [--directory D]    results/<campaign>/report.html of a finished
                                              run
    leopod compare ORBIT REFERENCE [--sv ID] [--reference-sv ID] [--time-system S]
                   [--helmert 3|6|7] [--figure PNG]
                                              ORBIT minus REFERENCE in inertial R, T, N: mean,
                                              STD and RMS per day and in total (SP3, leopod
                                              netCDF or GRACE CSV files; leopod.validation)

``CAMPAIGN`` is one or more campaign files, merged in order (as Snakemake's ``--configfile``);
its files go to ``results/<campaign>/``, ``resources/<campaign>/`` and ``logs/<campaign>/`` of
``D`` (:mod:`leopod.workflow.layout`), so campaigns run in one directory keep their files.
Relative input paths of a campaign are relative to the working directory ``D`` (default: the
current directory), as for Snakemake. ``check`` exits with 2 when the campaign does not conform
to the schema, 1 when input files are missing, 0 otherwise; it reports inputs that the workflow
writes itself (simulated data, downloads) as such. ``run --exclude-failed`` exits with 1 when
it left days out, ``init`` with 2 on a bad argument or an existing file, ``status`` when a job failed (leopod.workflow.status). ``compare`` exits with
1 when a file cannot be read or the two orbits have no common span.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from collections.abc import Sequence
from pathlib import Path

__all__ = ["main", "missing_inputs"]

#: The checkout holding the Snakefile (leopod runs from its checkout).
REPO = Path(__file__).resolve().parents[2]


def missing_inputs(config: dict, directory: Path) -> tuple[dict[str, list[str]], dict[str, str]]:
    """Input files a validated campaign names that do not exist.

    Parameters
    ----------
    config : dict
        The validated campaign.
    directory : Path
        Working directory (relative paths are relative to it).

    Returns
    -------
    missing : dict
        ``{config entry: [missing file, ...]}`` for the entries named by path (per campaign
        day for daily templates), only entries with missing files.
    produced : dict
        ``{config entry: "simulated" | "downloaded"}`` of the inputs the workflow writes.
    """
    from leopod.workflow.campaign import (
        campaign_days,
        campaign_inputs,
        expand_template,
        input_references,
        is_daily_template,
        produced_kind,
    )
    from leopod.workflow.downloads import PREFIX

    days = campaign_days(config)
    missing: dict[str, list[str]] = {}
    produced: dict[str, str] = {}
    for entry, container, key in input_references(campaign_inputs(config)):
        template = container.get(key)
        if not template:
            continue
        kind = ("downloaded" if template.startswith(PREFIX)
                else produced_kind(template, config))
        if kind:
            produced[entry] = kind
            continue
        sat = entry.split(".")[1] if entry.startswith("satellites.") else None
        files = ([expand_template(template, day, sat) for day in days]
                 if is_daily_template(template)
                 else [template.replace("{sat}", sat) if sat else template])
        gone = [f for f in dict.fromkeys(files) if not (directory / f).is_file()]
        if gone:
            missing[entry] = gone
    return missing, produced


def _check(args) -> int:
    from leopod.workflow.config import campaign_problems, read_campaign, validated

    raw = read_campaign(*args.campaign)
    problems = campaign_problems(raw)
    if problems:
        print(f"{len(problems)} problem(s) in the campaign:")
        for p in problems:
            print(f"  - {p}")
        return 2
    config = validated(raw)
    directory = args.directory.resolve()
    try:
        missing, produced = missing_inputs(config, directory)
    except ValueError as error:   # an input path the campaign's folders cannot hold
        print(f"1 problem(s) in the campaign:\n  - {error}")
        return 2
    print(f"campaign {config['campaign']}: {config['start_date']} to {config['end_date']}, "
          f"satellites {', '.join(config['satellites'])}: conforms to the schema")
    for entry, kind in produced.items():
        print(f"  {entry}: {kind} by the workflow")
    if not missing:
        print(f"  every input file named by path exists (below {directory})")
        return 0
    _print_missing(missing)
    print("days whose files are missing fail alone in a run; the others go on")
    return 1


def _print_missing(missing: dict[str, list[str]], prefix: str = "  ", file=None) -> None:
    """One line per config entry with missing input files (the first three named)."""
    for entry, files in missing.items():
        shown = ", ".join(files[:3]) + (f" and {len(files) - 3} more" if len(files) > 3 else "")
        print(f"{prefix}{entry}: {len(files)} file(s) missing: {shown}", file=file)


def _warn_missing(args) -> None:
    """Before a run (a dry run too, which Snakemake plans without complaint: the files are
    located by jobs): the input files of the campaign that do not exist, as warnings."""
    try:
        missing, _ = missing_inputs(_campaign(args), args.directory.resolve())
    except ValueError:    # leopod check names campaign problems; Snakemake stops on them
        return
    if missing:
        print("leopod run: warning: input files missing (their days will fail alone):",
              file=sys.stderr)
        _print_missing(missing, prefix="  warning: ", file=sys.stderr)


def _snakemake(args, extra: Sequence[str]) -> list[str]:
    cmd = [str(Path(sys.executable).with_name("snakemake")), "--snakefile",
           str(REPO / "Snakefile"), "--directory", str(args.directory.resolve())]
    return cmd + [*extra, "--configfile", *[str(p.resolve()) for p in args.campaign]]


def _campaign(args) -> dict:
    from leopod.workflow.config import load_campaign

    return load_campaign(*args.campaign)


def _run(args) -> int:
    extra = ["--cores", str(args.cores)]
    if args.profile:
        extra += ["--profile", str(REPO / "profiles" / args.profile)
                  if (REPO / "profiles" / args.profile).is_dir() else args.profile]
    if args.exclude_failed:
        extra.append("--keep-going")
    _warn_missing(args)
    cmd = _snakemake(args, [*extra, *args.snakemake])
    print(" ".join(cmd), flush=True)
    status = _execute(cmd, args.progress)
    if status == 0 or not args.exclude_failed:
        return status
    import yaml

    from leopod.workflow.campaign import pod_days
    from leopod.workflow.layout import Layout
    from leopod.workflow.status import failed_days, failures

    config = _campaign(args)
    layout = Layout.of(config)
    overlay = args.directory.resolve() / layout.failed_days
    # the days given in the campaign and those found here: data unusable, or POD failed
    excluded = {key: dict(config[key]) for key in ("exclude_days", "exclude_pod_days")}
    found = False
    # each pass leaves out at least one more day: a day's POD (held back by the code-bias map
    # of its period) may fail only once the days with bad data are out of the way
    while status != 0:
        failed = failed_days(failures(args.directory, layout), pod_days(_campaign(args)))
        if not failed:
            print("leopod run: the run failed, but no day has a failed job of its own "
                  "(see the Snakemake output above)", file=sys.stderr)
            break
        found = True
        for day, f in failed.items():
            excluded["exclude_pod_days" if f.in_pod else "exclude_days"][day] = f.reason
        overlay.parent.mkdir(parents=True, exist_ok=True)
        overlay.write_text(yaml.safe_dump(excluded, sort_keys=True, width=1000))
        print(f"{len(failed)} day(s) failed, run again without them ({overlay}):")
        for day, f in failed.items():
            print(f"  {day}  {f.reason}")
        if overlay not in args.campaign:
            args.campaign = [*args.campaign, overlay]
        cmd = _snakemake(args, [*extra, *args.snakemake])
        print(" ".join(cmd), flush=True)
        status = _execute(cmd, args.progress)
    _status(args)
    return status or int(found)


def _execute(cmd: list[str], progress: str) -> int:
    """Run Snakemake: its own output, or with ``progress`` (``on``, or ``auto`` on a
    terminal) the compact lines of :mod:`leopod.workflow.progress`."""
    if progress == "on" or (progress == "auto" and sys.stdout.isatty()):
        from leopod.workflow.progress import run_with_progress

        return run_with_progress(cmd)
    return subprocess.run(cmd).returncode


def _init(args) -> int:
    import datetime as dt

    from leopod.download.catalogue import Catalogue
    from leopod.workflow.init import campaign_text, read_satellites, write_campaign

    try:
        start, end = (dt.date.fromisoformat(value) for value in (args.start, args.end))
    except ValueError as error:
        print(f"leopod init: --start/--end: {error} (expected YYYY-MM-DD)", file=sys.stderr)
        return 2
    try:
        text, notes = campaign_text(
            args.name, args.satellite, start, end, system=args.system, products=args.products,
            catalogue=Catalogue.from_yaml(REPO / "config" / "catalogue.yaml"),
            satellites=read_satellites(REPO / "config" / "satellites.yaml"))
        path = write_campaign(args.directory / f"{args.name}.yaml", text,
                              overwrite=args.force)
    except (ValueError, FileExistsError) as error:
        print(f"leopod init: {error}", file=sys.stderr)
        return 2
    print(f"wrote {path}")
    for note in notes:
        print(f"  note: {note}")
    print(f"next: leopod check {path}; leopod run {path}")
    return 0


def _status(args) -> int:
    from leopod.workflow.campaign import excluded_days, pod_days, satellite_ids
    from leopod.workflow.layout import Layout
    from leopod.workflow.status import failed_days, failures, gate_verdicts, orbit_days

    config = _campaign(args)
    layout = Layout.of(config)
    days, excluded = pod_days(config), excluded_days(config)
    found = failures(args.directory, layout)
    failed = failed_days(found, days)
    print(f"campaign {config['campaign']}: {len(days)} day(s) "
          f"({config['start_date']} to {config['end_date']}"
          + (f", {len(excluded)} excluded" if excluded else "") + ")")
    products = config["products"]
    fixed = config["ambiguity"]["enabled"] and (products.get("wl_bias") or products.get("osb"))
    solutions = (["float_pod"] + (["fixed_pod"] if fixed else [])
                 if products.get("gnss_clock") else [])   # the solutions of common.smk
    for sat in satellite_ids(config):
        for solution in solutions:
            done = orbit_days(args.directory, layout, solution, sat, days)
            print(f"  {sat} {solution}: {len(done)} of {len(days)} day(s) with an orbit")
            for day, verdict in gate_verdicts(args.directory, layout, solution, sat,
                                              done).items():
                print(f"    {day}  quality gate {verdict}")
    for day, reason in excluded.items():
        print(f"  {day}  excluded: {reason}")
    for day, f in failed.items():
        print(f"  {day}  failed: {f.reason} ({f.log})")
    others = [f for f in found if f.day is None or f.day not in days + list(excluded)]
    for f in others:
        print(f"  failed job {f.rule} {f.wildcards}: {f.message} ({f.log})")
    return 1 if failed or others else 0


def _report(args) -> int:
    from leopod.workflow.layout import Layout

    out = args.directory.resolve() / Layout.of(_campaign(args)).report
    cmd = _snakemake(args, ["--report", str(out)])
    print(" ".join(cmd), flush=True)
    return subprocess.run(cmd).returncode


def _compare(args) -> int:
    import numpy as np

    from leopod.validation.compare import compare_orbits, to_gps_time
    from leopod.validation.orbit_statistics import orbit_statistics
    from leopod.validation.reference import read_reference_orbit

    try:
        orbit = read_reference_orbit([args.orbit], sv=args.sv)
        reference = read_reference_orbit([args.reference], sv=args.reference_sv or args.sv)
        system = orbit.attrs.get("time_system", "GPS")
        orbit = orbit.assign_coords(time=to_gps_time(orbit.time.values, system))
        diff = compare_orbits(orbit, reference, reference_time_system=args.time_system,
                              helmert=args.helmert)
    except (OSError, ValueError) as error:   # leopod's FormatError is a ValueError
        print(f"leopod compare: {error}", file=sys.stderr)
        return 1
    ok = np.isfinite(diff.diff_rtn_m.values).all(axis=1)
    stats = orbit_statistics(diff.isel(time=np.flatnonzero(ok)))
    print(f"{args.orbit} minus {args.reference}: {int(ok.sum())} common epochs "
          f"({int((~ok).sum())} of the orbit's without reference), reference time system "
          f"{diff.attrs['reference_time_system']}, inertial R/T/N of the reference"
          + (f", {args.helmert}-parameter Helmert removed" if args.helmert else ""))
    print(f"{'period':<12s} {'epochs':>7s}  " + "  ".join(
        f"{kind + ' ' + c:>9s}" for kind in ("mean", "STD", "RMS") for c in ("R", "T", "N", "3D"))
          + "   [cm]")
    for period in stats.period.values:
        row = stats.sel(period=period)
        print(f"{period:<12s} {int(row.n_epochs):7d}  " + "  ".join(
            f"{100 * float(row[name].sel(component=c)):9.2f}"
            for name in ("mean_m", "std_m", "rms_m") for c in ("R", "T", "N", "3D")))
    if args.figure:
        from leopod.plots.validation import plot_reference_differences

        plot_reference_differences(diff, args.figure,
                                   title=f"{Path(args.orbit).name} vs {Path(args.reference).name}")
        print(f"figure: {args.figure}")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``leopod`` command (module docstring); returns the exit status."""
    parser = argparse.ArgumentParser(prog="leopod", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("init", help="write a new campaign file",
                       description="write NAME.yaml: a commented campaign whose inputs are "
                                   "download families of the catalogue")
    p.add_argument("name", help="campaign name (letters, digits, '-', '_', '.')")
    p.add_argument("--satellite", required=True,
                   help="satellite key (config/satellites.yaml knows grace-a, grace-b, hy-2b, "
                        "hy-2d; others get placeholders)")
    p.add_argument("--start", required=True, help="first day, YYYY-MM-DD (GPS time)")
    p.add_argument("--end", required=True, help="last day, YYYY-MM-DD (inclusive)")
    p.add_argument("--system", default="G",
                   help="GNSS of the POD: G, C, E or several letters for a combined POD")
    p.add_argument("--products", default="cod",
                   help="product set: cod, cod-osb, grg, wum, whu (leopod.workflow.init)")
    p.add_argument("--directory", "-d", type=Path, default=Path.cwd(),
                   help="folder of the new file (default: the current one)")
    p.add_argument("--force", action="store_true", help="replace an existing file")
    for name, text in (("check", "check a campaign and its input files"),
                       ("run", "run a campaign (Snakemake)"),
                       ("status", "the days with an orbit and the failed jobs of a run"),
                       ("report", "build results/<campaign>/report.html of a run")):
        p = sub.add_parser(name, help=text, description=text)
        p.add_argument("campaign", type=Path, nargs="+", help="campaign file(s), merged in order")
        p.add_argument("--directory", "-d", type=Path, default=Path.cwd(),
                       help="working directory (default: the current one)")
        if name == "run":
            p.add_argument("--cores", "-c", type=int, default=2)
            p.add_argument("--profile", default=None,
                           help="Snakemake profile: a folder of the checkout's profiles/ "
                                "(e.g. slurm) or a path")
            p.add_argument("--progress", choices=("on", "off", "auto"), default="auto",
                           help="one line per started and finished job instead of "
                                "Snakemake's output (auto: on a terminal)")
            p.add_argument("--exclude-failed", action="store_true",
                           help="keep going past failed jobs, then run again without the "
                                "days that have one (results/<campaign>/failed_days.yaml)")
    p = sub.add_parser("compare", help="compare an orbit with a reference orbit",
                       description="ORBIT minus REFERENCE in inertial R/T/N, per day and in total")
    p.add_argument("orbit", help="orbit file (SP3, leopod netCDF or GRACE CSV)")
    p.add_argument("reference", help="reference orbit file (same formats)")
    p.add_argument("--sv", help="satellite id in the SP3 files (default: the only one)")
    p.add_argument("--reference-sv", help="satellite id in the reference SP3 (default: --sv)")
    p.add_argument("--time-system", choices=("GPS", "TAI", "TT", "UTC"),
                   help="time system of the reference's epochs (default: its header, else GPS)")
    p.add_argument("--helmert", type=int, choices=(3, 6, 7),
                   help="estimate and remove a Helmert transformation with this many parameters")
    p.add_argument("--figure", type=Path, help="PNG of the differences over time")
    argv = list(sys.argv[1:] if argv is None else argv)
    # everything after the first "--" goes to Snakemake as it is
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    args = parser.parse_args(argv[:argv.index("--")] if "--" in argv else argv)
    args.snakemake = extra
    return {"init": _init, "check": _check, "run": _run, "status": _status, "report": _report,
            "compare": _compare}[args.command](args)


if __name__ == "__main__":
    sys.exit(main())
