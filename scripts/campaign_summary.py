"""Snakemake script of rule campaign_summary: see leopod.validation.summary."""

import xarray as xr

from leopod.io import write_text
from leopod.io.netcdf import write_netcdf
from leopod.validation.summary import COLUMNS, campaign_table, day_row
from leopod.workflow.log import configure_logging


def _load(files: dict, key: str, date: str):
    path = files.get(key, {}).get(date)
    return xr.load_dataset(path) if path else None


def main(inp, out, params, log):
    rows = []
    for solution in params.solutions:
        files = params.files[solution]
        for date in params.days:
            rows.append(day_row(date, solution, residuals=_load(files, "residuals", date),
                                ambiguity=_load(files, "ambiguity", date),
                                overlap=_load(files, "overlap", date),
                                reference=_load(files, "reference", date),
                                slr=_load(files, "slr", date)))
    table = campaign_table(rows)
    log.info("campaign summary:\n%s", table.to_string(float_format=lambda v: f"{v:.3g}"))
    ds = xr.Dataset.from_dataframe(table.reset_index().rename_axis("row"))
    for name, (unit, text) in COLUMNS.items():
        ds[name].attrs.update(units=unit, long_name=text)
    for name in ("date", "solution"):
        ds[name].attrs.update(units="1", long_name=name)
    write_netcdf(ds, out.nc, step="campaign_summary", inputs=list(inp), time_system="GPS",
                 title=f"campaign summary {params.title}")
    write_text(out.csv, table.to_csv(float_format="%.4f"))
    header = "".join(f"<th title='{text}'>{name}<br>[{unit}]</th>"
                     for name, (unit, text) in COLUMNS.items())
    body = "\n".join(
        "<tr><td>{}</td><td>{}</td>{}</tr>".format(
            d, s, "".join(f"<td>{v:.3g}</td>" for v in row.to_numpy()))
        for (d, s), row in table.iterrows())
    write_text(out.html, f"<html><body><h3>{params.title}: campaign summary</h3>"
                         f"<table border='1' cellpadding='3'><tr><th>day</th><th>solution</th>"
                         f"{header}</tr>\n{body}</table></body></html>\n")


if __name__ == "__main__":
    log = configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    main(snakemake.input, snakemake.output, snakemake.params, log)  # noqa: F821
