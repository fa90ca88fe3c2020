// Checks of an Exodus II or CGNS file with the format's own libraries (VTK's libexodus and
// libcgns, and NetCDF) before VTK's reader sees it. Both readers misbehave on a file they cannot open:
// VTK's Exodus reader turns the Exodus library's verbose mode on (its errors then go to stderr),
// and VTK's CGNS reader ends the process (cgio_error_exit) when a file or one of its nodes cannot
// be opened. Opening the file here, quietly, and walking the CGNS tree's metadata (the nodes VTK
// reads) turns those cases into an InputError.
#include "io/vtk/vtk_check.h"

#include <vtk_cgns.h>
#include <vtk_exodusII.h>
#include <vtk_netcdf.h>

#include <vtkcgns/src/cgnslib.h>

#include <string>

#include "topotet/error.h"

namespace topotet::io::vtk {

ExodusQuiet::ExodusQuiet() : previous_(exoptval) { ex_opts(0); }
ExodusQuiet::~ExodusQuiet() { ex_opts(previous_); }
void ExodusQuiet::again() { ex_opts(0); }

void check_exodus(const std::string& path) {
  // The Exodus library prints (and turns its verbose mode on) when it cannot open a file: NetCDF,
  // which it is written on, is asked first, quietly, with Exodus's own global attributes.
  int nc = -1;
  if (const int status = nc_open(path.c_str(), NC_NOWRITE, &nc); status != NC_NOERR)
    throw InputError(path + ": not a readable Exodus II file (" + std::string(nc_strerror(status)) + ")");
  const bool exodus = nc_inq_att(nc, NC_GLOBAL, "version", nullptr, nullptr) == NC_NOERR &&
                      nc_inq_att(nc, NC_GLOBAL, "floating_point_word_size", nullptr, nullptr) == NC_NOERR;
  nc_close(nc);
  if (!exodus) throw InputError(path + ": not an Exodus II file, or a truncated one (a NetCDF file without Exodus's global attributes)");
  ExodusQuiet quiet;
  int cpu_word_size = 8, io_word_size = 0;
  float version = 0.0f;
  const int id = ex_open(path.c_str(), EX_READ, &cpu_word_size, &io_word_size, &version);
  if (id < 0) throw InputError(path + ": not a readable Exodus II file (the Exodus library cannot open it)");
  ex_init_params params{};
  const int status = ex_get_init_ext(id, &params);
  ex_close(id);
  if (status < 0) throw InputError(path + ": not a readable Exodus II file (no valid header)");
}

void check_cgns(const std::string& path) {
  int fn = -1;
  if (cg_open(path.c_str(), CG_MODE_READ, &fn) != CG_OK)
    throw InputError(path + ": not a readable CGNS file (" + cg_get_error() + ")");
  const auto bad = [&](const std::string& where) {
    const std::string why = cg_get_error();
    cg_close(fn);
    throw InputError(path + ": damaged CGNS file: " + where + (why.empty() ? "" : " (" + why + ")"));
  };
  int bases = 0;
  if (cg_nbases(fn, &bases) != CG_OK) bad("the bases");
  for (int b = 1; b <= bases; ++b) {
    char name[64] = {};
    int cell_dim = 0, phys_dim = 0, zones = 0;
    if (cg_base_read(fn, b, name, &cell_dim, &phys_dim) != CG_OK || cg_nzones(fn, b, &zones) != CG_OK)
      bad("base " + std::to_string(b));
    for (int z = 1; z <= zones; ++z) {
      const std::string zone = "base " + std::to_string(b) + ", zone " + std::to_string(z);
      cgsize_t size[9] = {};
      CGNS_ENUMT(ZoneType_t) type;
      int coords = 0, sections = 0, sols = 0, bocos = 0;
      if (cg_zone_read(fn, b, z, name, size) != CG_OK || cg_zone_type(fn, b, z, &type) != CG_OK ||
          cg_ncoords(fn, b, z, &coords) != CG_OK || cg_nsols(fn, b, z, &sols) != CG_OK ||
          cg_nbocos(fn, b, z, &bocos) != CG_OK)
        bad(zone);
      for (int c = 1; c <= coords; ++c) {
        CGNS_ENUMT(DataType_t) data_type;
        if (cg_coord_info(fn, b, z, c, &data_type, name) != CG_OK) bad(zone + ", coordinate " + std::to_string(c));
      }
      if (type == CGNS_ENUMV(Unstructured)) {
        if (cg_nsections(fn, b, z, &sections) != CG_OK) bad(zone + ", its sections");
        for (int s = 1; s <= sections; ++s) {
          CGNS_ENUMT(ElementType_t) element_type;
          cgsize_t start = 0, end = 0, data_size = 0;
          int nbndry = 0, parent_flag = 0;
          if (cg_section_read(fn, b, z, s, name, &element_type, &start, &end, &nbndry, &parent_flag) != CG_OK ||
              cg_ElementDataSize(fn, b, z, s, &data_size) != CG_OK)
            bad(zone + ", section " + std::to_string(s));
        }
      }
      for (int s = 1; s <= sols; ++s) {
        CGNS_ENUMT(GridLocation_t) location;
        int fields = 0;
        if (cg_sol_info(fn, b, z, s, name, &location) != CG_OK || cg_nfields(fn, b, z, s, &fields) != CG_OK)
          bad(zone + ", solution " + std::to_string(s));
        for (int f = 1; f <= fields; ++f) {
          CGNS_ENUMT(DataType_t) data_type;
          if (cg_field_info(fn, b, z, s, f, &data_type, name) != CG_OK)
            bad(zone + ", solution " + std::to_string(s) + ", field " + std::to_string(f));
        }
      }
      for (int bc = 1; bc <= bocos; ++bc) {
        CGNS_ENUMT(BCType_t) bc_type;
        CGNS_ENUMT(PointSetType_t) set_type;
        CGNS_ENUMT(DataType_t) normal_type;
        cgsize_t points = 0, normal_size = 0;
        int normal_index[3] = {}, datasets = 0;
        if (cg_boco_info(fn, b, z, bc, name, &bc_type, &set_type, &points, normal_index, &normal_size, &normal_type,
                         &datasets) != CG_OK)
          bad(zone + ", boundary condition " + std::to_string(bc));
      }
    }
  }
  cg_close(fn);
}

}  // namespace topotet::io::vtk
