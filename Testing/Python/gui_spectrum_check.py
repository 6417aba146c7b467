"""GUI test of the spectrum, part 3 (run by test_gui.sh with the state file and paraview's
exit status): DimensionReduction applied from the Filters menu opened no view for its
Spectrum port (the render view alone, showing the reduction); Show Spectrum, reached
through Filters > Multichannel, opened one bar chart of the Spectrum port: X the
component column 'index', only the eigenvalues plotted, the method in the title."""

from gui_checks import arguments, check, finish, state_with_data

path, rc = arguments()
s = state_with_data(path, rc, "small_64D.nii")
before = s.get("before")
if check(before is not None, "Filters > Multichannel > Show Spectrum called the helper"):
    check([v["type"] for v in before] == ["RenderView"] and
          any(name.startswith("DimensionReduction") and port == 0
              for name, port in before[0]["shown"]) and
          not any(port == 1 for v in before for _, port in v["shown"]),
          "Apply of DimensionReduction opened no chart: one render view showing the "
          "reduction, the Spectrum port nowhere (%s)" % before)
    after = s.get("after", [])
    charts = [v for v in after if v["type"] == "XYBarChartView"]
    check(len(after) == 2 and len(charts) == 1 and
          any(port == 1 for _, port in charts[0]["shown"]),
          "Show Spectrum added one bar chart of the Spectrum port (%s)" % after)
    chart = s.get("chart", {})
    pairs = chart.get("series") or []  # (series, visible) pairs as the proxy keeps them
    visible = [pairs[i] for i in range(0, len(pairs) - 1, 2) if pairs[i + 1] == "1"]
    check(chart.get("x") == "index" and chart.get("index_for_x") == 0 and visible == ["value"],
          "X is the component column, only the eigenvalues are bars: %s" % chart)
    check(str(s.get("text", "")).startswith("Spectrum: PCA spectrum: 3 components kept"),
          "the status text names it: %r" % s.get("text"))
finish("gui_spectrum")
