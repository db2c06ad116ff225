// core/io/hdf5_layout.cpp writes the dimension-scale attributes itself, once each: HDF5's
// own dimension-scale API must read them as it reads those H5DSattach_scale writes (each
// dataset's axes attached to their scales, each scale listing its datasets in the order
// they were attached).
#include <gtest/gtest.h>
#include <hdf5.h>
#include <hdf5_hl.h>

#include <string>
#include <vector>

#include "core/io/hdf5_layout.hpp"

namespace packsim {
namespace {

void dataset(hid_t file, const char* path, int rank, const hsize_t* dims) {
  const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  const hid_t space = H5Screate_simple(rank, dims, nullptr);
  const hid_t ds = H5Dcreate2(file, path, H5T_NATIVE_DOUBLE, space, lcpl, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(ds, 0) << path;
  H5Dclose(ds);
  H5Sclose(space);
  H5Pclose(lcpl);
}

// The datasets attached to `scale`, in its REFERENCE_LIST's order, as "path:axis".
std::vector<std::string> referenceList(hid_t file, const char* scale) {
  struct Entry {
    hobj_ref_t ref;
    int dim;
  };
  const hid_t a = H5Aopen_by_name(file, scale, "REFERENCE_LIST", H5P_DEFAULT, H5P_DEFAULT);
  const hid_t space = H5Aget_space(a);
  std::vector<Entry> entries(static_cast<size_t>(H5Sget_simple_extent_npoints(space)));
  const hid_t type = H5Tcreate(H5T_COMPOUND, sizeof(Entry));
  H5Tinsert(type, "dataset", HOFFSET(Entry, ref), H5T_STD_REF_OBJ);
  H5Tinsert(type, "dimension", HOFFSET(Entry, dim), H5T_NATIVE_INT);
  H5Aread(a, type, entries.data());
  std::vector<std::string> out;
  for (Entry& e : entries) {
    const hid_t obj = H5Rdereference2(file, H5P_DEFAULT, H5R_OBJECT, &e.ref);
    char name[128] = "";
    H5Iget_name(obj, name, sizeof name);
    out.push_back(std::string(name) + ":" + std::to_string(e.dim));
    H5Oclose(obj);
  }
  H5Tclose(type);
  H5Sclose(space);
  H5Aclose(a);
  return out;
}

TEST(Hdf5Layout, DimensionScalesReadAsHdf5sOwnAttachments) {
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_fapl_core(fapl, 1 << 16, 0);  // in memory
  const hid_t file = H5Fcreate("layout-test.h5", H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  ASSERT_GE(file, 0);
  const hsize_t samples = 5, wide[2] = {5, 3};
  dataset(file, "/time_s", 1, &samples);
  dataset(file, "/truth/cell_voltage_V", 2, wide);
  dataset(file, "/truth/current_A", 1, &samples);
  dataset(file, "/bms/pack_voltage_V", 1, &samples);
  addNetcdfLayout(file, {samples, 3, 3, 0, 1});

  const hid_t time = H5Dopen2(file, "/time_s", H5P_DEFAULT);
  const hid_t cell = H5Dopen2(file, "/truth/cell", H5P_DEFAULT);
  ASSERT_GE(cell, 0);
  EXPECT_EQ(H5DSis_scale(time), 1);
  EXPECT_EQ(H5DSis_scale(cell), 1);
  for (const char* path : {"/truth/cell_voltage_V", "/truth/current_A", "/bms/pack_voltage_V"}) {
    const hid_t ds = H5Dopen2(file, path, H5P_DEFAULT);
    EXPECT_EQ(H5DSis_attached(ds, time, 0), 1) << path;
    EXPECT_EQ(H5DSget_num_scales(ds, 0), 1) << path;
    H5Dclose(ds);
  }
  const hid_t wideDs = H5Dopen2(file, "/truth/cell_voltage_V", H5P_DEFAULT);
  EXPECT_EQ(H5DSis_attached(wideDs, cell, 1), 1);
  EXPECT_EQ(H5DSget_num_scales(wideDs, 1), 1);
  H5Dclose(wideDs);
  // In the order of attachment: the datasets by name, each one's axes in order.
  EXPECT_EQ(referenceList(file, "/time_s"),
            (std::vector<std::string>{"/bms/pack_voltage_V:0", "/truth/cell_voltage_V:0", "/truth/current_A:0"}));
  EXPECT_EQ(referenceList(file, "/truth/cell"), (std::vector<std::string>{"/truth/cell_voltage_V:1"}));
  H5Dclose(cell);
  H5Dclose(time);
  H5Fclose(file);
  H5Pclose(fapl);
}

}  // namespace
}  // namespace packsim
