#include "vtkHapticBoxChartTables.h"
#include "evaluation/comparison.h"
#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <algorithm>

vtkSmartPointer<vtkTable> vtkHapticBoxChartTables::SweepTable(const std::vector<hb::SweepRow>& rows) {
  auto table = vtkSmartPointer<vtkTable>::New();
  vtkNew<vtkStringArray> method;
  method->SetName("Method");
  vtkNew<vtkIntArray> m, n, pareto;
  m->SetName("M");
  n->SetName("N");
  pareto->SetName("Pareto");
  vtkNew<vtkDoubleArray> ns, bytes, bake, median, p95, agreement;
  ns->SetName("QueryNs");
  bytes->SetName("MemoryBytes");
  bake->SetName("BakeSeconds");
  median->SetName("ForceErrorMedianPercent");
  p95->SetName("ForceErrorP95Percent");
  agreement->SetName("ContactAgreementPercent");
  for (const hb::SweepRow& r : rows) {
    method->InsertNextValue(r.method);
    m->InsertNextValue(r.m);
    n->InsertNextValue(r.n);
    pareto->InsertNextValue(r.pareto ? 1 : 0);
    ns->InsertNextValue(r.query_ns);
    bytes->InsertNextValue(double(r.memory_bytes));
    bake->InsertNextValue(r.bake_seconds);
    median->InsertNextValue(100.0 * r.force_error_median);
    p95->InsertNextValue(100.0 * r.force_error_p95);
    agreement->InsertNextValue(100.0 * r.contact_agreement);
  }
  table->AddColumn(method);
  table->AddColumn(m);
  table->AddColumn(n);
  table->AddColumn(ns);
  table->AddColumn(bytes);
  table->AddColumn(bake);
  table->AddColumn(median);
  table->AddColumn(p95);
  table->AddColumn(agreement);
  table->AddColumn(pareto);
  return table;
}

vtkSmartPointer<vtkTable> vtkHapticBoxChartTables::HistogramTable(const std::vector<double>& errors, int bins,
                                                                  double upper) {
  bins = std::max(bins, 1);
  if (!(upper > 0.0)) upper = std::max(1e-9, hb::quantile(errors, 0.99));
  std::vector<double> counts(std::size_t(bins), 0.0);
  const double width = upper / bins;
  for (double e : errors) counts[std::size_t(std::clamp(int(e / width), 0, bins - 1))] += 1.0;
  vtkNew<vtkDoubleArray> centre, count;
  centre->SetName("ErrorPercent");
  count->SetName("Probes");
  for (int b = 0; b < bins; ++b) {
    centre->InsertNextValue(100.0 * (b + 0.5) * width);
    count->InsertNextValue(counts[std::size_t(b)]);
  }
  auto table = vtkSmartPointer<vtkTable>::New();
  table->AddColumn(centre);
  table->AddColumn(count);
  return table;
}
