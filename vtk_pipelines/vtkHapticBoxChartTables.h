/**
 * @class   vtkHapticBoxChartTables
 * @brief   Sweep rows and error samples as vtkTables, for VTK charts (vtkChartXY) in the
 *          desktop window: the same data the report draws with PLplot.
 */
#ifndef vtkHapticBoxChartTables_h
#define vtkHapticBoxChartTables_h

#include "evaluation/sweep.h"
#include <vtkSmartPointer.h>
#include <vector>

class vtkTable;

class vtkHapticBoxChartTables {
public:
  /**
   * One row per sweep row. Columns: "Method" (string), "M", "N" (int, 0 for references),
   * "QueryNs", "MemoryBytes", "BakeSeconds", "ForceErrorMedianPercent",
   * "ForceErrorP95Percent", "ContactAgreementPercent" (double), "Pareto" (int 0/1).
   */
  static vtkSmartPointer<vtkTable> SweepTable(const std::vector<hb::SweepRow>& rows);

  /**
   * Histogram of relative errors (fractions) over [0, upper] in `bins` bins (values above
   * go to the last bin; upper <= 0: the 99th percentile). Columns: "ErrorPercent" (bin
   * centre, %), "Probes" (count).
   */
  static vtkSmartPointer<vtkTable> HistogramTable(const std::vector<double>& errors, int bins = 40, double upper = 0.0);
};

#endif
