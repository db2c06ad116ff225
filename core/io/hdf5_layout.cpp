#include "core/io/hdf5_layout.hpp"

#include <hdf5_hl.h>

#include "core/sim/result_channels.hpp"

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace packsim {

namespace {

class Obj {
 public:
  explicit Obj(hid_t id, const std::string& what) : id_(id) {
    if (id_ < 0) throw std::runtime_error("HDF5: cannot open " + what);
  }
  ~Obj() { H5Oclose(id_); }
  Obj(const Obj&) = delete;
  Obj& operator=(const Obj&) = delete;
  operator hid_t() const { return id_; }

 private:
  hid_t id_;
};

void check(herr_t e, const std::string& what) {
  if (e < 0) throw std::runtime_error("HDF5: cannot " + what);
}

std::string baseName(const std::string& path) { return path.substr(path.rfind('/') + 1); }
std::string parentOf(const std::string& path) {
  const size_t slash = path.rfind('/');
  return slash == 0 ? "/" : path.substr(0, slash);
}
std::string join(const std::string& group, const std::string& name) { return (group == "/" ? "" : group) + "/" + name; }

bool hasAttr(hid_t obj, const char* name) { return H5Aexists(obj, name) > 0; }

void stringAttr(hid_t obj, const char* name, const std::string& value) {
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.empty() ? 1 : value.size());
  H5Tset_cset(type, H5T_CSET_UTF8);
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  const herr_t e = a < 0 ? -1 : H5Awrite(a, type, value.c_str());
  if (a >= 0) H5Aclose(a);
  H5Sclose(space);
  H5Tclose(type);
  check(e, std::string("write attribute ") + name);
}

std::string longNameOf(const std::string& path) {
  if (const ResultChannel* c = findResultChannel(path)) return c->long_name;
  if (path == "/events") return "events: time_s, kind, detail";
  if (path == "/bus_trace") return "monitor-bus transactions: time_s, bus, direction, count, bytes, what";
  if (path == "/can_trace") return "CAN frames of a board alone: time_s, end_s, direction, id, dlc, data, lost";
  // truth/cell_voltage_V -> "cell voltage (truth)"
  std::string name = baseName(path);
  const size_t unit = name.rfind('_');
  if (unit != std::string::npos && unit + 1 < name.size() && name.find_first_of("ABCDEFGHIJKLMNOPQRSTUVWXYZ", unit) != std::string::npos)
    name.erase(unit);
  for (char& c : name)
    if (c == '_') c = ' ';
  const std::string group = baseName(parentOf(path));
  return group.empty() ? name : name + " (" + group + ")";
}

std::string dimensionName(const std::string& path, hsize_t length, const LayoutSizes& z) {
  const std::string name = baseName(path);
  if (const ResultChannel* c = findResultChannel(path); c && c->axis != Axis::None) return axisName(c->axis);
  const bool truth = parentOf(path) == "/truth";
  if (length == z.cells && (truth || length != z.series)) return "cell";
  if (length == z.series) return "series";
  if (length == z.thermistors) return "thermistor";
  if (length == z.devices) return "device";
  return name + "_index";
}

// Whether the object at `name` is a dataset, from its header's basic information (not
// by opening it: a dataset's open reads its layout, filters and fill value, some
// 60,000 instructions each).
bool isDataset(hid_t group, const char* name) {
#if H5_VERSION_GE(1, 12, 0)
  H5O_info2_t info;
  if (H5Oget_info_by_name3(group, name, &info, H5O_INFO_BASIC, H5P_DEFAULT) < 0) throw std::runtime_error("HDF5: cannot read " + std::string(name));
#else
  H5O_info_t info;
  if (H5Oget_info_by_name2(group, name, &info, H5O_INFO_BASIC, H5P_DEFAULT) < 0) throw std::runtime_error("HDF5: cannot read " + std::string(name));
#endif
  return info.type == H5O_TYPE_DATASET;
}

std::vector<std::string> datasetPaths(hid_t file) {
  std::vector<std::string> out;
  auto visit = [](hid_t group, const char* name, const H5L_info_t*, void* data) -> herr_t {
    try {
      if (isDataset(group, name)) static_cast<std::vector<std::string>*>(data)->push_back(std::string("/") + name);
    } catch (const std::exception&) {
      return -1;  // (no exception through HDF5's C frames)
    }
    return 0;
  };
  check(H5Lvisit(file, H5_INDEX_NAME, H5_ITER_INC, visit, &out), "list the datasets");
  return out;
}

class Layout {
 public:
  Layout(hid_t file, const LayoutSizes& z) : file_(file), z_(z) {}
  Layout(const Layout&) = delete;
  Layout& operator=(const Layout&) = delete;

  void run() {
    const std::vector<std::string> paths = datasetPaths(file_);  // before any link is added
    {
      Obj time(H5Dopen2(file_, "/time_s", H5P_DEFAULT), "/time_s");
      check(H5DSset_scale(time, "time_s"), "make /time_s a dimension scale");
    }
    for (const std::string& p : paths) describe(p);
    for (const auto& [address, scale] : scaleUses_) writeReferenceList(scale.path, scale.uses);
  }

 private:
  void describe(const std::string& path) {
    Obj ds(H5Dopen2(file_, path.c_str(), H5P_DEFAULT), path);
    if (!hasAttr(ds, "long_name")) stringAttr(ds, "long_name", longNameOf(path));
    if (path == "/time_s") return;
    hid_t space = H5Dget_space(ds);
    hsize_t dims[2] = {0, 0};
    const int rank = H5Sget_simple_extent_dims(space, dims, nullptr);
    H5Sclose(space);
    if (rank < 1 || rank > 2) return;
    const std::string group = parentOf(path);
    std::string scales[2];
    if (group == "/inputs") {  // a batch case's drawn values: one per cell
      scales[0] = indexScale(group, "cell", dims[0]);
    } else if (dims[0] == z_.samples && path != "/events" && path != "/bus_trace" && path != "/can_trace") {
      scales[0] = timeScale(group);
    } else {
      scales[0] = indexScale(group, path == "/events" ? "event" : baseName(path) + "_index", dims[0]);
    }
    if (rank == 2) scales[1] = indexScale(group, dimensionName(path, dims[1], z_), dims[1]);
    attach(ds, path, rank, scales);
  }

  // Dimension scales attached as H5DSattach_scale attaches them (HDF5 1.10, object
  // references): the dataset's DIMENSION_LIST holds each axis's scale, and each scale's
  // REFERENCE_LIST (dataset, axis) for every attachment in the order they were made. The
  // lists are written once each: DIMENSION_LIST here, every REFERENCE_LIST after the last
  // dataset (writeReferenceList). H5DSattach_scale read, deleted and wrote again the
  // scale's whole list at each attachment: /time_s, which nearly every channel has, cost
  // some 170,000 instructions a channel.
  void attach(hid_t ds, const std::string& path, int rank, const std::string (&scales)[2]) {
    hobj_ref_t self;
    check(H5Rcreate(&self, ds, ".", H5R_OBJECT, -1), "make a reference to " + path);
    hobj_ref_t axisScale[2];
    hvl_t lists[2];
    for (int axis = 0; axis < rank; ++axis) {
      const std::string& scalePath = scales[axis];
      check(H5Rcreate(&axisScale[axis], file_, scalePath.c_str(), H5R_OBJECT, -1), "make a reference to " + scalePath);
      lists[axis].len = 1;
      lists[axis].p = &axisScale[axis];
      ScaleUses& uses = scaleUses_[axisScale[axis]];  // by the object: /time_s has a link in each group
      if (uses.path.empty()) uses.path = scalePath;
      uses.uses.push_back({self, axis});
    }
    const hsize_t n = static_cast<hsize_t>(rank);
    const hid_t type = H5Tvlen_create(H5T_STD_REF_OBJ);
    const hid_t space = H5Screate_simple(1, &n, nullptr);
    const hid_t a = H5Acreate2(ds, "DIMENSION_LIST", type, space, H5P_DEFAULT, H5P_DEFAULT);
    const herr_t e = a < 0 ? -1 : H5Awrite(a, type, lists);
    if (a >= 0) H5Aclose(a);
    H5Sclose(space);
    H5Tclose(type);
    check(e, "attach the dimension scales of " + path);
  }

  // One REFERENCE_LIST entry: H5DS's ds_list_t (the dataset, the axis the scale is of).
  struct ScaleUse {
    hobj_ref_t dataset;
    int dimension;
  };
  struct ScaleUses {
    std::string path;  // a link to the scale
    std::vector<ScaleUse> uses;
  };

  void writeReferenceList(const std::string& scalePath, const std::vector<ScaleUse>& uses) {
    const hid_t type = H5Tcreate(H5T_COMPOUND, sizeof(ScaleUse));
    H5Tinsert(type, "dataset", HOFFSET(ScaleUse, dataset), H5T_STD_REF_OBJ);
    H5Tinsert(type, "dimension", HOFFSET(ScaleUse, dimension), H5T_NATIVE_INT);
    const hsize_t n = uses.size();
    const hid_t space = H5Screate_simple(1, &n, nullptr);
    const hid_t a = H5Acreate_by_name(file_, scalePath.c_str(), "REFERENCE_LIST", type, space, H5P_DEFAULT, H5P_DEFAULT,
                                      H5P_DEFAULT);
    const herr_t e = a < 0 ? -1 : H5Awrite(a, type, uses.data());
    if (a >= 0) H5Aclose(a);
    H5Sclose(space);
    H5Tclose(type);
    check(e, "attach dimension scale " + scalePath);
  }

  // /time_s, hard-linked into `group` on first use.
  std::string timeScale(const std::string& group) {
    const std::string link = join(group, "time_s");
    if (group != "/" && H5Lexists(file_, link.c_str(), H5P_DEFAULT) <= 0)
      check(H5Lcreate_hard(file_, "/time_s", file_, link.c_str(), H5P_DEFAULT, H5P_DEFAULT), "link " + link);
    return link;
  }

  // group/name holding 1..length; a name already taken with another length gets a suffix.
  std::string indexScale(const std::string& group, std::string name, hsize_t length) {
    for (int k = 2;; ++k) {
      const std::string path = join(group, name);
      if (const auto it = indexLength_.find(path); it != indexLength_.end()) {  // one made here: its length known
        if (it->second == length) return path;
      } else if (H5Lexists(file_, path.c_str(), H5P_DEFAULT) <= 0) {
        indexLength_.emplace(path, length);
        return createIndex(path, name, length);
      } else {
        Obj existing(H5Dopen2(file_, path.c_str(), H5P_DEFAULT), path);
        hid_t space = H5Dget_space(existing);
        hsize_t n = 0;
        H5Sget_simple_extent_dims(space, &n, nullptr);
        H5Sclose(space);
        if (n == length && H5DSis_scale(existing) > 0) return path;
      }
      name = baseName(path) + "_" + std::to_string(k);
    }
  }

  std::string createIndex(const std::string& path, const std::string& name, hsize_t length) {
    std::vector<int32_t> index(length);
    for (hsize_t i = 0; i < length; ++i) index[i] = static_cast<int32_t>(i + 1);
    hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_obj_track_times(dcpl, 0);
    hid_t space = H5Screate_simple(1, &length, nullptr);
    const hid_t id = H5Dcreate2(file_, path.c_str(), H5T_NATIVE_INT32, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    H5Sclose(space);
    H5Pclose(dcpl);
    if (id < 0) throw std::runtime_error("HDF5: cannot create " + path);
    Obj ds(id, path);  // closed on leaving, thrown or not
    check(length ? H5Dwrite(ds, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, index.data()) : 0,
          "write dimension scale " + path);
    check(H5DSset_scale(ds, name.c_str()), "write dimension scale " + path);
    stringAttr(ds, "long_name", name + " number (1-based)");  // while open (no second open)
    return path;
  }

  hid_t file_;
  LayoutSizes z_;
  std::map<hobj_ref_t, ScaleUses> scaleUses_;   // every scale's attachments, by the scale
  std::map<std::string, hsize_t> indexLength_;  // index scales created here, by path: their length
};

}  // namespace

void addNetcdfLayout(hid_t file, const LayoutSizes& sizes) { Layout(file, sizes).run(); }

}  // namespace packsim
