// Makes a written result file readable by netCDF tools (xarray/h5netcdf, netCDF-C,
// Panoply): one pass over every dataset the writer produced, named and given dimensions
// from the result-channel table, so a new channel gets them without a line of its own.
//
//   /time_s                  dimension scale "time_s"; hard-linked into every group
//                            (/truth/time_s is the same dataset, not a copy), so a
//                            group opened on its own has its time coordinate
//   <group>/cell, series,    dimension scales 1..k (int32) for the second axis of the
//   thermistor, device, ...  group's 2-D datasets (the channel table's axis)
//   /event                   dimension scale 1..k of the events table
//   every dataset            `long_name` (the result-channel table,
//                            core/sim/result_channels.hpp) and `units` where it has one
//
// Chunking and compression (deflate + shuffle) are set when a dataset is created
// (hdf5_writer.cpp); values are unchanged.
#pragma once
#include <hdf5.h>

#include <cstddef>

namespace packsim {

struct LayoutSizes {
  size_t samples = 0, cells = 0, series = 0, thermistors = 0, devices = 0;
};

void addNetcdfLayout(hid_t file, const LayoutSizes& sizes);

}  // namespace packsim
