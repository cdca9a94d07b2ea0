#include "mesh/mesh_io.h"
#include "test_meshes.h"
#include "vtkHapticBoxMeshReader.h"
#include <gtest/gtest.h>
#include <vtkPointData.h>
#include <vtkPolyDataWriter.h>
#include <vtkSTLWriter.h>
#include <vtkXMLPolyDataWriter.h>
#include <cstdio>
#include <fstream>

namespace {

vtkSmartPointer<vtkPolyData> Read(const std::string& path, bool viaVTK = false) {
  vtkNew<vtkHapticBoxMeshReader> reader;
  reader->SetFileName(path.c_str());
  reader->SetUseVTKReaders(viaVTK);
  reader->Update();
  return reader->GetOutput();
}

} // namespace

TEST(MeshReaderTest, ReadsOffLikeTheCore) {
  const std::string path = hb::test::ScratchPath("sphere.off");
  const hb::TriangleMesh mesh = hb::make_sphere(1.f, 2);
  hb::write_mesh(mesh, path);
  const hb::TriangleMesh core = hb::read_mesh(path);
  vtkSmartPointer<vtkPolyData> pd = Read(path);
  EXPECT_EQ(pd->GetNumberOfPoints(), vtkIdType(core.vertex_count()));
  EXPECT_EQ(pd->GetNumberOfPolys(), vtkIdType(core.triangle_count()));
  EXPECT_NE(pd->GetPointData()->GetNormals(), nullptr);
  std::remove(path.c_str());
}

TEST(MeshReaderTest, ReadsVtkXmlLegacyAndStl) {
  vtkSmartPointer<vtkPolyData> sphere = hb::test::SpherePolyData(2);
  const std::string vtp = hb::test::ScratchPath("sphere.vtp");
  const std::string legacy = hb::test::ScratchPath("sphere.vtk");
  const std::string stl = hb::test::ScratchPath("sphere.stl");
  vtkNew<vtkXMLPolyDataWriter> w1;
  w1->SetInputData(sphere);
  w1->SetFileName(vtp.c_str());
  w1->Write();
  vtkNew<vtkPolyDataWriter> w2;
  w2->SetInputData(sphere);
  w2->SetFileName(legacy.c_str());
  w2->Write();
  vtkNew<vtkSTLWriter> w3;
  w3->SetInputData(sphere);
  w3->SetFileName(stl.c_str());
  w3->Write();
  for (const std::string& p : {vtp, legacy}) {
    vtkSmartPointer<vtkPolyData> pd = Read(p);
    EXPECT_EQ(pd->GetNumberOfPoints(), sphere->GetNumberOfPoints()) << p;
    EXPECT_EQ(pd->GetNumberOfPolys(), sphere->GetNumberOfPolys()) << p;
    std::remove(p.c_str());
  }
  // STL has no shared vertices: the core merges them, VTK's reader too (by default).
  EXPECT_EQ(Read(stl)->GetNumberOfPolys(), sphere->GetNumberOfPolys());
  EXPECT_EQ(Read(stl, true)->GetNumberOfPolys(), sphere->GetNumberOfPolys());
  std::remove(stl.c_str());
}

TEST(MeshReaderTest, MissingAndGarbageFilesFailWithEmptyOutput) {
  vtkObject::GlobalWarningDisplayOff();
  EXPECT_EQ(Read("/nonexistent/x.off")->GetNumberOfPoints(), 0);
  const std::string junk = hb::test::ScratchPath("junk.off");
  std::ofstream(junk) << "OFF\n3 1 0\n0 0 nan\n1 0 0\n0 1 0\n3 0 1 2\n";
  EXPECT_EQ(Read(junk)->GetNumberOfPoints(), 0);
  std::remove(junk.c_str());
  vtkObject::GlobalWarningDisplayOn();
}

TEST(MeshReaderTest, CanReadFileByExtension) {
  EXPECT_TRUE(vtkHapticBoxMeshReader::CanReadFile("a.OFF"));
  EXPECT_TRUE(vtkHapticBoxMeshReader::CanReadFile("a.vtp"));
  EXPECT_FALSE(vtkHapticBoxMeshReader::CanReadFile("a.xyz"));
}
