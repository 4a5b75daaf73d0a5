#include "granpack/io/hdf5_store.h"
#include "granpack/comm/communicator.h"

#include <hdf5.h>
#include <sys/resource.h>
#include <sys/statvfs.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include "granpack/comm/allgather.h"
#include "granpack/comm/broadcast.h"
#include "granpack/comm/collective_error.h"
#include "granpack/comm/fault_injection.h"
#include "granpack/comm/id_consistency.h"
#include "granpack/comm/reduce.h"
#include "granpack/comm/scan.h"
#include "granpack/io/atomic_file.h"
#include "granpack/io/hdf5_handle.h"
#include "granpack/io/hdf5_header_guard.h"
#include "granpack/io/hdf5_string_guard.h"
#include "granpack/io/mpiio_hints.h"
#include "granpack/io/xdmf.h"

#ifndef GRANPACK_VERSION
#define GRANPACK_VERSION "unknown"
#endif

namespace granpack {

namespace {

using h5::Handle;

bool& file_left_open() {
  static bool left = false;
  return left;
}

std::function<void(std::string_view)>& write_hook() {
  static std::function<void(std::string_view)> hook;
  return hook;
}
void run_write_hook(std::string_view stage) {
  if (write_hook())
    write_hook()(stage);
}

/// Like collectively(), but a bad-input failure on any rank becomes an InputError on every
/// rank (collectively() rethrows a plain Error carrying the exit code).
template <class F> void collectively_typed(MPI_Comm comm, F&& f) {
  try {
    collectively(comm, std::forward<F>(f));
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    if (e.exit_code() == kExitBadInput)
      throw InputError(e.what());
    throw;
  }
}

/// The file being read or written: every failure names it, and the HDF5 detail is appended.
/// Reading failures are bad input (InputError); writing failures are runtime errors.
struct FileContext {
  std::filesystem::path path;
  bool reading = true;
  /// The objects (by path) whose attribute messages the header guard has checked already.
  mutable std::set<std::string> guarded{};

  [[noreturn]] void fail(const std::string& what, bool with_hdf5_detail = false) const {
    std::string msg = path.string() + ": " + what;
    if (with_hdf5_detail) {
      const std::string detail = h5::last_error_detail();
      if (!detail.empty())
        msg += " (HDF5: " + detail + ")";
    }
    if (reading)
      throw InputError(msg);
    throw Error(msg);
  }
  hid_t id(hid_t id, const std::string& what) const {
    if (id < 0)
      fail(what, true);
    return id;
  }
  void rc(herr_t rc, const std::string& what) const {
    if (rc < 0)
      fail(what, true);
  }
};

// ----------------------------------------------------------------------------------------
// Types

template <class T> hid_t mem_type();
template <> hid_t mem_type<double>() {
  return H5T_NATIVE_DOUBLE;
}
template <> hid_t mem_type<std::int64_t>() {
  return H5T_NATIVE_INT64;
}
template <> hid_t mem_type<std::uint32_t>() {
  return H5T_NATIVE_UINT32;
}
template <> hid_t mem_type<int>() {
  return H5T_NATIVE_INT;
}

template <class T> hid_t file_type();
template <> hid_t file_type<double>() {
  return H5T_IEEE_F64LE;
}
template <> hid_t file_type<std::int64_t>() {
  return H5T_STD_I64LE;
}
template <> hid_t file_type<std::uint32_t>() {
  return H5T_STD_U32LE;
}
template <> hid_t file_type<int>() {
  return H5T_STD_I32LE;
}

template <class T> H5T_class_t type_class() {
  return std::is_floating_point_v<T> ? H5T_FLOAT : H5T_INTEGER;
}
template <class T> const char* type_name() {
  return std::is_floating_point_v<T> ? "floating-point" : "integer";
}

// ----------------------------------------------------------------------------------------
// Attributes

Handle scalar_space(const FileContext& ctx) {
  return h5::dataspace_handle(ctx.id(H5Screate(H5S_SCALAR), "cannot create a dataspace"));
}

/// A numeric attribute of `space`'s shape (scalar, or 1-D for the stress target's per-axis values).
template <class T>
void write_attribute_values(const FileContext& ctx, hid_t obj, const char* name, const T* values,
                            hid_t space) {
  auto attr = h5::attribute_handle(
      ctx.id(H5Acreate2(obj, name, file_type<T>(), space, H5P_DEFAULT, H5P_DEFAULT),
             std::string("cannot create attribute ") + name));
  ctx.rc(H5Awrite(attr, mem_type<T>(), values), std::string("cannot write attribute ") + name);
}

template <class T>
void write_attribute(const FileContext& ctx, hid_t obj, const char* name, T value) {
  write_attribute_values(ctx, obj, name, &value, scalar_space(ctx));
}

template <class T>
void write_attribute(const FileContext& ctx, hid_t obj, const char* name, const std::vector<T>& v) {
  const hsize_t n = v.size();
  auto space = h5::dataspace_handle(
      ctx.id(H5Screate_simple(1, &n, nullptr), std::string("cannot create attribute ") + name));
  write_attribute_values(ctx, obj, name, v.data(), space);
}

/// Variable-length UTF-8 string attribute (h5py reads it as str).
void write_attribute(const FileContext& ctx, hid_t obj, const char* name, const std::string& s) {
  auto type = h5::datatype_handle(ctx.id(H5Tcopy(H5T_C_S1), "cannot create a string type"));
  ctx.rc(H5Tset_size(type, H5T_VARIABLE), "cannot create a string type");
  ctx.rc(H5Tset_cset(type, H5T_CSET_UTF8), "cannot create a string type");
  auto space = scalar_space(ctx);
  auto attr =
      h5::attribute_handle(ctx.id(H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT),
                                  std::string("cannot create attribute ") + name));
  const char* p = s.c_str();
  ctx.rc(H5Awrite(attr, type, &p), std::string("cannot write attribute ") + name);
}

/// Before HDF5 decodes the attribute messages of `obj` (at path `where`): the header guard,
/// once per object and file context (every lookup decodes all of the object's messages).
void guard_attributes(const FileContext& ctx, hid_t obj, const std::string& where) {
  const std::string at = where.empty() ? "/" : where;
  if (ctx.guarded.insert(at).second)
    h5::check_attribute_messages(ctx.path, obj, "attributes of " + at);
}

/// Whether `obj` (at path `where`) has the attribute; an HDF5 failure is an error.
bool attribute_exists(const FileContext& ctx, hid_t obj, const std::string& where,
                      const char* name) {
  guard_attributes(ctx, obj, where);
  const htri_t exists = H5Aexists(obj, name);
  if (exists < 0)
    ctx.fail("cannot look up attribute " + where + name, true);
  return exists > 0;
}

/// length: none for a single value, n for a 1-D array of n values.
Handle open_attribute(const FileContext& ctx, hid_t obj, const std::string& where, const char* name,
                      std::optional<std::size_t> length = std::nullopt) {
  if (!attribute_exists(ctx, obj, where, name))
    ctx.fail("missing attribute " + where + name);
  auto attr = h5::attribute_handle(
      ctx.id(H5Aopen(obj, name, H5P_DEFAULT), "cannot open attribute " + where + name));
  auto space =
      h5::dataspace_handle(ctx.id(H5Aget_space(attr), "cannot read attribute " + where + name));
  if (!length && H5Sget_simple_extent_npoints(space) != 1)
    ctx.fail("attribute " + where + name + " is not a single value");
  if (length && (H5Sget_simple_extent_ndims(space) != 1 ||
                 H5Sget_simple_extent_npoints(space) != static_cast<hssize_t>(*length)))
    ctx.fail("attribute " + where + name + " is not an array of " + std::to_string(*length) +
             " values");
  return attr;
}

template <class T>
std::vector<T> read_attribute_values(const FileContext& ctx, hid_t obj, const std::string& where,
                                     const char* name, std::optional<std::size_t> length) {
  auto attr = open_attribute(ctx, obj, where, name, length);
  auto type =
      h5::datatype_handle(ctx.id(H5Aget_type(attr), "cannot read attribute " + where + name));
  if (H5Tget_class(type) != type_class<T>())
    ctx.fail("attribute " + where + name + " is not " + type_name<T>());
  std::vector<T> values(length.value_or(1));
  ctx.rc(H5Aread(attr, mem_type<T>(), values.data()), "cannot read attribute " + where + name);
  return values;
}

template <class T>
T read_attribute(const FileContext& ctx, hid_t obj, const std::string& where, const char* name) {
  return read_attribute_values<T>(ctx, obj, where, name, std::nullopt)[0];
}

/// Deflate, the strongest filter HDF5 ships, compresses at most about 1032:1.
constexpr std::uint64_t kMaxCompression = 1100;

/// A corrupt or forged file may declare datasets of any size: n_particles = 2^40 with datasets
/// of that shape and no storage behind them reads back as fill values, and the reader would
/// allocate terabytes. So `bytes` may be read only if the dataset holds them in the file:
/// all of them when unfiltered (granpack writes contiguous datasets, allocated in full), at
/// most kMaxCompression times its stored size when compressed (e.g. after h5repack).
void check_storage(const FileContext& ctx, hid_t dset, const std::string& what,
                   std::uint64_t bytes) {
  if (bytes == 0)
    return;
  std::error_code ec;
  const std::uint64_t file_size = std::filesystem::file_size(ctx.path, ec);
  const std::uint64_t stored = H5Dget_storage_size(dset);
  auto dcpl =
      h5::plist_handle(ctx.id(H5Dget_create_plist(dset), "cannot read the layout of " + what));
  const int filters = H5Pget_nfilters(dcpl);
  if (filters < 0)
    ctx.fail("cannot read the filters of " + what, true);
  const std::uint64_t factor = filters > 0 ? kMaxCompression : 1;
  if (ec || stored > file_size || bytes / factor > stored)
    ctx.fail(what + " declares " + std::to_string(bytes) + " bytes of data but the file holds " +
             std::to_string(stored) + " for it (the file is " +
             (ec ? std::string("of unknown size") : std::to_string(file_size) + " bytes") +
             "): corrupt or inconsistent file");
}

/// Reads a scalar string from an attribute or a dataset, fixed- or variable-length.
std::string read_string(const FileContext& ctx, hid_t obj, bool is_attribute,
                        const std::string& what) {
  auto type = h5::datatype_handle(
      ctx.id(is_attribute ? H5Aget_type(obj) : H5Dget_type(obj), "cannot read " + what));
  if (H5Tget_class(type) != H5T_STRING)
    ctx.fail(what + " is not a string");
  auto space = h5::dataspace_handle(
      ctx.id(is_attribute ? H5Aget_space(obj) : H5Dget_space(obj), "cannot read " + what));
  if (H5Sget_simple_extent_npoints(space) != 1)
    ctx.fail(what + " is not a single string");
  const htri_t variable = H5Tis_variable_str(type);
  if (variable < 0)
    ctx.fail("cannot read " + what, true);
  if (variable > 0) {
    // HDF5 1.10.8 follows the stored heap reference blindly (hangs, crashes, 21 GB).
    h5::check_variable_string(ctx.path, obj, is_attribute, what);
    auto mtype = h5::datatype_handle(ctx.id(H5Tcopy(H5T_C_S1), "cannot read " + what));
    ctx.rc(H5Tset_size(mtype, H5T_VARIABLE), "cannot read " + what);
    ctx.rc(H5Tset_cset(mtype, H5Tget_cset(type)), "cannot read " + what);
    char* p = nullptr;
    ctx.rc(is_attribute ? H5Aread(obj, mtype, &p)
                        : H5Dread(obj, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, &p),
           "cannot read " + what);
    std::string s = p ? p : "";
    if (p) {
      if (is_attribute) {
        H5free_memory(p);
      } else {
        H5Dvlen_reclaim(mtype, space, H5P_DEFAULT, &p);
      }
    }
    return s;
  }
  const std::size_t size = H5Tget_size(type);
  if (size == 0)
    ctx.fail("cannot read " + what, true);
  // The declared length is allocated below: bound it by what the file holds.
  if (!is_attribute) {
    check_storage(ctx, obj, what, size);
  } else {
    std::error_code ec;
    const auto file_size = std::filesystem::file_size(ctx.path, ec);
    if (ec || size > file_size)
      ctx.fail(what + " declares a string of " + std::to_string(size) +
               " bytes, longer than the file: corrupt file");
  }
  auto mtype = h5::datatype_handle(ctx.id(H5Tcopy(H5T_C_S1), "cannot read " + what));
  ctx.rc(H5Tset_size(mtype, size), "cannot read " + what);
  ctx.rc(H5Tset_strpad(mtype, H5T_STR_NULLPAD), "cannot read " + what);
  ctx.rc(H5Tset_cset(mtype, H5Tget_cset(type)), "cannot read " + what);
  std::string s(size, '\0');
  ctx.rc(is_attribute ? H5Aread(obj, mtype, s.data())
                      : H5Dread(obj, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, s.data()),
         "cannot read " + what);
  s.resize(std::strlen(s.c_str())); // strip the padding
  return s;
}

std::string read_string_attribute(const FileContext& ctx, hid_t obj, const std::string& where,
                                  const char* name) {
  auto attr = open_attribute(ctx, obj, where, name);
  return read_string(ctx, attr, true, "attribute " + where + name);
}

// ----------------------------------------------------------------------------------------
// Datasets: each rank's rows [offset, offset + count) of an [n] or [n, cols] array.

/// A rank's contiguous slice of the rows of a dataset.
struct Slice {
  std::int64_t global = 0; ///< rows in the file
  std::int64_t offset = 0; ///< first row of this rank
  std::int64_t count = 0;  ///< rows of this rank (may be 0)
};

/// cols == 0: a 1-D dataset [n]; otherwise [n, cols].
std::vector<hsize_t> shape(std::int64_t rows, int cols) {
  if (cols == 0)
    return {static_cast<hsize_t>(rows)};
  return {static_cast<hsize_t>(rows), static_cast<hsize_t>(cols)};
}

Handle group_create(const FileContext& ctx, hid_t file, const char* name) {
  return h5::group_handle(ctx.id(H5Gcreate2(file, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                                 std::string("cannot create group ") + name));
}

Handle group_open(const FileContext& ctx, hid_t file, const char* name) {
  const htri_t exists = H5Lexists(file, name, H5P_DEFAULT);
  if (exists < 0)
    ctx.fail(std::string("cannot look up group ") + name, true);
  if (exists == 0)
    ctx.fail(std::string("missing group ") + name);
  return h5::group_handle(
      ctx.id(H5Gopen2(file, name, H5P_DEFAULT), std::string("cannot open group ") + name));
}

/// Selects this rank's rows of `space` (a dataset's or a memory dataspace), or nothing.
void select_rows(const FileContext& ctx, hid_t space, std::int64_t first, std::int64_t count,
                 int cols, const std::string& what) {
  if (count == 0) {
    ctx.rc(H5Sselect_none(space), "cannot select in " + what);
    return;
  }
  std::vector<hsize_t> cnt = shape(count, cols), st(cnt.size(), 0);
  st[0] = static_cast<hsize_t>(first);
  ctx.rc(H5Sselect_hyperslab(space, H5S_SELECT_SET, st.data(), nullptr, cnt.data(), nullptr),
         "cannot select in " + what);
}

/// Collective: creates group/name with the global shape and writes this rank's rows.
template <class T>
void write_rows(const FileContext& ctx, hid_t group, const std::string& gname, const char* name,
                const std::vector<T>& local, const Slice& slice, int cols, const char* unit,
                hid_t dxpl) {
  const std::string what = gname + "/" + name;
  const auto dims = shape(slice.global, cols);
  auto fspace = h5::dataspace_handle(
      ctx.id(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
             "cannot create the dataspace of " + what));
  auto dcpl = h5::plist_handle(ctx.id(H5Pcreate(H5P_DATASET_CREATE), "cannot create " + what));
  ctx.rc(H5Pset_fill_time(dcpl, H5D_FILL_TIME_NEVER), "cannot create " + what);
  auto dset = h5::dataset_handle(
      ctx.id(H5Dcreate2(group, name, file_type<T>(), fspace, H5P_DEFAULT, dcpl, H5P_DEFAULT),
             "cannot create dataset " + what));
  write_attribute(ctx, dset, "unit", std::string(unit));
  if (slice.global == 0)
    return; // nothing to write, on every rank
  select_rows(ctx, fspace, slice.offset, slice.count, cols, what);
  const auto mdims = shape(std::max<std::int64_t>(slice.count, 1), cols);
  auto mspace = h5::dataspace_handle(
      ctx.id(H5Screate_simple(static_cast<int>(mdims.size()), mdims.data(), nullptr),
             "cannot create a memory dataspace for " + what));
  select_rows(ctx, mspace, 0, slice.count, cols, what);
  const T dummy{};
  const T* data = slice.count > 0 ? local.data() : &dummy;
  ctx.rc(H5Dwrite(dset, mem_type<T>(), mspace, fspace, dxpl, data), "cannot write " + what);
}

/// Opens group/name and checks its type class and shape against (rows, cols).
template <class T>
Handle open_rows(const FileContext& ctx, hid_t group, const std::string& gname, const char* name,
                 std::int64_t rows, int cols) {
  const std::string what = gname + "/" + name;
  const htri_t exists = H5Lexists(group, name, H5P_DEFAULT);
  if (exists < 0)
    ctx.fail("cannot look up dataset " + what, true);
  if (exists == 0)
    ctx.fail("missing dataset " + what);
  auto dset =
      h5::dataset_handle(ctx.id(H5Dopen2(group, name, H5P_DEFAULT), "cannot open dataset " + what));
  auto type = h5::datatype_handle(ctx.id(H5Dget_type(dset), "cannot read dataset " + what));
  if (H5Tget_class(type) != type_class<T>())
    ctx.fail("dataset " + what + " is not " + type_name<T>());
  auto space = h5::dataspace_handle(ctx.id(H5Dget_space(dset), "cannot read dataset " + what));
  const int rank = H5Sget_simple_extent_ndims(space);
  if (rank < 0)
    ctx.fail("cannot read the shape of dataset " + what, true);
  const auto want = shape(rows, cols);
  std::vector<hsize_t> dims(std::max(rank, 1), 0);
  if (rank > 0)
    H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  if (static_cast<std::size_t>(rank) != want.size() || dims != want) {
    auto fmt = [](const std::vector<hsize_t>& d, int r) {
      std::string s = "[";
      for (int k = 0; k < r; ++k)
        s += (k ? ", " : "") + std::to_string(d[k]);
      return s + "]";
    };
    ctx.fail("dataset " + what + " has shape " + fmt(dims, rank) + ", expected " +
             fmt(want, static_cast<int>(want.size())) +
             " (from the root attributes n_particles/n_contacts and dimension)");
  }
  // In the file's element size (an f32 dataset stores 4 bytes per value; HDF5 converts).
  const std::uint64_t row_bytes =
      static_cast<std::uint64_t>(std::max(cols, 1)) * std::max<std::size_t>(H5Tget_size(type), 1);
  const auto n_rows = static_cast<std::uint64_t>(rows);
  const std::uint64_t max_rows = std::numeric_limits<std::uint64_t>::max() / row_bytes;
  check_storage(ctx, dset, "dataset " + what,
                n_rows > max_rows ? std::numeric_limits<std::uint64_t>::max() : n_rows * row_bytes);
  return dset;
}

/// Collective: reads this rank's rows of an already validated dataset.
template <class T>
std::vector<T> read_rows(const FileContext& ctx, hid_t dset, const std::string& what,
                         const Slice& slice, int cols, hid_t dxpl) {
  const std::size_t width = cols == 0 ? 1 : static_cast<std::size_t>(cols);
  std::vector<T> out(static_cast<std::size_t>(slice.count) * width);
  if (slice.global == 0)
    return out;
  auto fspace = h5::dataspace_handle(ctx.id(H5Dget_space(dset), "cannot read " + what));
  select_rows(ctx, fspace, slice.offset, slice.count, cols, what);
  const auto mdims = shape(std::max<std::int64_t>(slice.count, 1), cols);
  auto mspace = h5::dataspace_handle(
      ctx.id(H5Screate_simple(static_cast<int>(mdims.size()), mdims.data(), nullptr),
             "cannot create a memory dataspace for " + what));
  select_rows(ctx, mspace, 0, slice.count, cols, what);
  T dummy{};
  ctx.rc(H5Dread(dset, mem_type<T>(), mspace, fspace, dxpl, slice.count > 0 ? out.data() : &dummy),
         "cannot read " + what);
  return out;
}

/// Flattens n fixed-size Eigen vectors into row-major [n, size] doubles.
template <class V> std::vector<double> flatten(const std::vector<V>& v, std::size_t n) {
  std::vector<double> out;
  out.reserve(n * V::SizeAtCompileTime);
  for (std::size_t i = 0; i < n; ++i)
    for (int a = 0; a < V::SizeAtCompileTime; ++a)
      out.push_back(v[i][a]);
  return out;
}

template <class V> V row(const std::vector<double>& flat, std::size_t i) {
  V v;
  for (int a = 0; a < V::SizeAtCompileTime; ++a)
    v[a] = flat[i * V::SizeAtCompileTime + a];
  return v;
}

// ----------------------------------------------------------------------------------------
// /parameters: the contact law and stress target in force (io/state_parameters.h)

const char* normal_law_name(NormalLawKind k) {
  return k == NormalLawKind::kHertz ? "hertz" : "linear";
}
const char* tangential_law_name(TangentialStiffnessKind k) {
  return k == TangentialStiffnessKind::kMindlin ? "mindlin"
         : k == TangentialStiffnessKind::kRatio ? "ratio"
                                                : "constant";
}

/// The numeric attributes of /parameters that hold a contact-law parameter, with its member.
constexpr std::pair<const char*, double ContactLawParams::*> kLawNumbers[] = {
    {"young_modulus", &ContactLawParams::young_modulus},
    {"poisson_ratio", &ContactLawParams::poisson_ratio},
    {"normal_stiffness", &ContactLawParams::k_n},
    {"tangential_stiffness", &ContactLawParams::k_t},
    {"tangential_stiffness_ratio", &ContactLawParams::k_t_ratio},
    {"damping", &ContactLawParams::damping_ratio},
    {"friction", &ContactLawParams::friction},
    {"cohesion_force", &ContactLawParams::cohesion_force},
    {"cohesion_range", &ContactLawParams::cohesion_range},
    {"rolling_stiffness", &ContactLawParams::rolling_stiffness},
    {"rolling_friction", &ContactLawParams::rolling_friction},
    {"rolling_damping", &ContactLawParams::rolling_damping}};

/// Collective (attributes: every rank passes the same values).
void write_parameters(const FileContext& ctx, hid_t file, const StateParameters& p, int dim) {
  auto g = group_create(ctx, file, "parameters");
  const ContactLawParams& law = p.contact_law;
  write_attribute(ctx, g, "normal_law", std::string(normal_law_name(law.normal)));
  write_attribute(ctx, g, "tangential_law", std::string(tangential_law_name(law.tangential)));
  write_attribute(ctx, g, "walton_rescaling", law.walton_rescaling ? 1 : 0);
  write_attribute(ctx, g, "damping_tension", law.damping_tension ? 1 : 0);
  for (const auto& [name, member] : kLawNumbers)
    write_attribute(ctx, g, name, law.*member);
  const StressTarget& t = p.stress_target;
  std::vector<double> stress(dim, 0.0);
  std::vector<int> fixed(dim, 0);
  if (t.set()) {
    if (t.stress.size() != std::size_t(dim) || t.fixed.size() != std::size_t(dim))
      ctx.fail("the stress target has " + std::to_string(t.stress.size()) + " stresses and " +
               std::to_string(t.fixed.size()) + " fixed-axis flags for " + std::to_string(dim) +
               " axes");
    stress = t.stress;
    for (int a = 0; a < dim; ++a)
      fixed[a] = t.fixed[a] ? 1 : 0;
  }
  write_attribute(ctx, g, "stress_target_stage", t.stage);
  write_attribute(ctx, g, "stress_target", stress);
  write_attribute(ctx, g, "fixed_axes", fixed);
  write_attribute(ctx, g, "pressure_target", t.set() ? t.pressure : 0.0);
}

/// Not collective (metadata reads only).
StateParameters read_parameters(const FileContext& ctx, hid_t file, int dim) {
  auto g = group_open(ctx, file, "parameters");
  const std::string where = "/parameters/";
  auto number = [&](const char* name) { return read_attribute<double>(ctx, g, where, name); };
  StateParameters p;
  ContactLawParams& law = p.contact_law;
  const std::string normal = read_string_attribute(ctx, g, where, "normal_law");
  if (normal == "hertz")
    law.normal = NormalLawKind::kHertz;
  else if (normal == "linear")
    law.normal = NormalLawKind::kLinear;
  else
    ctx.fail("attribute " + where + "normal_law = '" + normal + "' (hertz or linear)");
  const std::string tangential = read_string_attribute(ctx, g, where, "tangential_law");
  if (tangential == "mindlin")
    law.tangential = TangentialStiffnessKind::kMindlin;
  else if (tangential == "ratio")
    law.tangential = TangentialStiffnessKind::kRatio;
  else if (tangential == "constant")
    law.tangential = TangentialStiffnessKind::kConstant;
  else
    ctx.fail("attribute " + where + "tangential_law = '" + tangential +
             "' (mindlin, ratio or constant)");
  law.walton_rescaling = read_attribute<int>(ctx, g, where, "walton_rescaling") != 0;
  // Written since 2026-12-06; older files had no choice (the damping could pull).
  law.damping_tension = !attribute_exists(ctx, g, where, "damping_tension") ||
                        read_attribute<int>(ctx, g, where, "damping_tension") != 0;
  for (const auto& [name, member] : kLawNumbers)
    law.*member = number(name);
  StressTarget& t = p.stress_target;
  t.stage = read_attribute<int>(ctx, g, where, "stress_target_stage");
  const auto stress = read_attribute_values<double>(ctx, g, where, "stress_target", dim);
  const auto fixed = read_attribute_values<int>(ctx, g, where, "fixed_axes", dim);
  const double pressure = number("pressure_target");
  if (t.stage < -1)
    ctx.fail("attribute " + where + "stress_target_stage is below -1");
  if (t.set()) {
    t.stress = stress;
    for (int f : fixed)
      t.fixed.push_back(f != 0);
    t.pressure = pressure;
  }
  return p;
}

// ----------------------------------------------------------------------------------------
// Files

Handle mpio_fapl(const FileContext& ctx, MPI_Comm comm) {
  auto fapl = h5::plist_handle(ctx.id(H5Pcreate(H5P_FILE_ACCESS), "cannot create a fapl"));
  // The hints of GRANPACK_MPIIO_HINTS (io/mpiio_hints.h); HDF5 keeps its own copy.
  MPI_Info info = mpiio_hints_info();
  const herr_t rc = H5Pset_fapl_mpio(fapl, comm, info);
  if (info != MPI_INFO_NULL)
    MPI_Info_free(&info);
  ctx.rc(rc, "cannot set the MPI-IO driver");
  return fapl;
}

Handle collective_dxpl(const FileContext& ctx) {
  auto dxpl = h5::plist_handle(ctx.id(H5Pcreate(H5P_DATASET_XFER), "cannot create a dxpl"));
  ctx.rc(H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE), "cannot set collective transfer");
  return dxpl;
}

/// Collective. Checks that the file exists and is HDF5, then opens it read-only on comm.
Handle open_for_reading(MPI_Comm comm, const FileContext& ctx) {
  h5::silence_errors();
  collectively_typed(comm, [&] {
    std::error_code ec;
    const auto status = std::filesystem::status(ctx.path, ec);
    if (!std::filesystem::exists(status))
      ctx.fail("no such file");
    if (!std::filesystem::is_regular_file(status))
      ctx.fail("not a regular file");
    const htri_t is_h5 = H5Fis_hdf5(ctx.path.c_str());
    if (is_h5 < 0)
      ctx.fail("cannot be read as HDF5", true);
    if (is_h5 == 0)
      ctx.fail("not an HDF5 file");
    // Open once with the serial driver first: a corrupt superblock then fails inside HDF5
    // (silenced; its detail goes into our message) instead of reaching Open MPI's I/O layer,
    // which prints "mca_fbtl_posix_preadv: error in (p)read(v)" for garbage offsets.
    h5::file_handle(ctx.id(H5Fopen(ctx.path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT),
                           "cannot open as HDF5 (truncated or corrupt?)"));
  });
  Handle file;
  collectively_typed(comm, [&] {
    auto fapl = mpio_fapl(ctx, comm);
    file = h5::file_handle(ctx.id(H5Fopen(ctx.path.c_str(), H5F_ACC_RDONLY, fapl),
                                  "cannot open as HDF5 (truncated or corrupt?)"));
  });
  return file;
}

/// A scalar fixed-length UTF-8 string dataset (parallel HDF5 cannot write variable-length
/// data), written by rank 0 alone with independent I/O. Collective (dataset creation), with
/// rank 0's text: the creation's metadata must be identical on every rank, or the file is
/// corrupted silently (a text that differs between ranks, e.g. by a clock reading, once
/// produced a checkpoint with garbage contact rows).
void write_text_dataset(const FileContext& ctx, hid_t file, MPI_Comm comm, const char* name,
                        const std::string& text) {
  const std::string what = std::string("dataset /") + name;
  const auto size =
      broadcast_value<unsigned long long>(comm, std::max<std::size_t>(text.size(), 1));
  auto type = h5::datatype_handle(ctx.id(H5Tcopy(H5T_C_S1), "cannot create " + what));
  ctx.rc(H5Tset_size(type, static_cast<std::size_t>(size)), "cannot create " + what);
  ctx.rc(H5Tset_strpad(type, H5T_STR_NULLPAD), "cannot create " + what);
  ctx.rc(H5Tset_cset(type, H5T_CSET_UTF8), "cannot create " + what);
  auto space = scalar_space(ctx);
  auto dset = h5::dataset_handle(
      ctx.id(H5Dcreate2(file, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
             "cannot create " + what));
  if (rank_of(comm) == 0) {
    std::string padded = text.empty() ? std::string(1, '\0') : text;
    ctx.rc(H5Dwrite(dset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, padded.data()),
           "cannot write " + what);
  }
}

/// Not collective (metadata reads only). Root attributes, /deck, /run_state, /parameters.
FileMeta read_meta(const FileContext& ctx, hid_t file) {
  const std::string root = "/";
  guard_attributes(ctx, file, root);
  const htri_t has_format = H5Aexists(file, "format");
  if (has_format <= 0)
    ctx.fail("not a granpack file (no root attribute 'format')");
  const std::string format = read_string_attribute(ctx, file, root, "format");
  if (format != "granpack")
    ctx.fail("not a granpack file (root attribute format = '" + format + "')");
  const int version = read_attribute<int>(ctx, file, root, "format_version");
  if (version < 1 || version > kHdf5FormatVersion)
    ctx.fail("format_version " + std::to_string(version) +
             " is not supported (this granpack reads versions 1 to " +
             std::to_string(kHdf5FormatVersion) + ")");
  FileMeta m;
  m.granpack_version = read_string_attribute(ctx, file, root, "granpack_version");
  m.dimension = read_attribute<int>(ctx, file, root, "dimension");
  if (m.dimension != 2 && m.dimension != 3)
    ctx.fail("root attribute dimension = " + std::to_string(m.dimension) + " (must be 2 or 3)");
  m.n_particles = read_attribute<std::int64_t>(ctx, file, root, "n_particles");
  m.n_contacts = read_attribute<std::int64_t>(ctx, file, root, "n_contacts");
  if (m.n_particles < 0 || m.n_contacts < 0)
    ctx.fail("negative n_particles or n_contacts in the root attributes");
  m.time = read_attribute<double>(ctx, file, root, "time");
  m.step = read_attribute<std::int64_t>(ctx, file, root, "step");
  m.stage_index = read_attribute<int>(ctx, file, root, "stage_index");
  m.stage_name = read_string_attribute(ctx, file, root, "stage_name");
  m.kind = read_string_attribute(ctx, file, root, "kind");
  const htri_t has_deck = H5Lexists(file, "deck", H5P_DEFAULT);
  if (has_deck < 0)
    ctx.fail("cannot look up dataset /deck", true);
  if (has_deck == 0)
    ctx.fail("missing dataset /deck");
  auto deck =
      h5::dataset_handle(ctx.id(H5Dopen2(file, "deck", H5P_DEFAULT), "cannot open dataset /deck"));
  m.deck_text = read_string(ctx, deck, false, "dataset /deck");
  // /run_state: only in checkpoints (the stage state a restart continues from).
  const htri_t has_state = H5Lexists(file, "run_state", H5P_DEFAULT);
  if (has_state < 0)
    ctx.fail("cannot look up dataset /run_state", true);
  if (has_state > 0) {
    auto state = h5::dataset_handle(
        ctx.id(H5Dopen2(file, "run_state", H5P_DEFAULT), "cannot open dataset /run_state"));
    m.run_state = read_string(ctx, state, false, "dataset /run_state");
  }
  // /parameters: absent from files written before it existed.
  const htri_t has_parameters = H5Lexists(file, "parameters", H5P_DEFAULT);
  if (has_parameters < 0)
    ctx.fail("cannot look up group /parameters", true);
  if (has_parameters > 0)
    m.parameters = read_parameters(ctx, file, m.dimension);
  return m;
}

/// Not collective. Reads a small [dim] dataset entirely (used for the cell).
template <int dim>
Vec<dim> read_small_vector(const FileContext& ctx, hid_t group, const char* name) {
  auto dset = open_rows<double>(ctx, group, "/cell", name, dim, 0);
  Vec<dim> v;
  ctx.rc(H5Dread(dset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()),
         std::string("cannot read /cell/") + name);
  return v;
}

template <int dim> Cell<dim> read_cell(const FileContext& ctx, hid_t file) {
  auto g = group_open(ctx, file, "cell");
  Cell<dim> cell;
  cell.length = read_small_vector<dim>(ctx, g, "length");
  cell.rate = read_small_vector<dim>(ctx, g, "rate");
  for (int a = 0; a < dim; ++a)
    if (!(cell.length[a] > 0) || !std::isfinite(cell.length[a]))
      ctx.fail("/cell/length has a non-positive or non-finite component");
  return cell;
}

/// Local consistency checks before any HDF5 call of a write.
template <int dim> void validate_for_write(const Configuration<dim>& c, const FileContext& ctx) {
  const auto& p = c.particles;
  const std::size_t n = p.n_owned();
  if (p.radius.size() < n || p.mass.size() < n || p.inertia.size() < n || p.position.size() < n ||
      p.velocity.size() < n || p.angular_velocity.size() < n || p.orientation.size() < n)
    ctx.fail("particle arrays shorter than the number of owned particles");
  for (std::size_t i = 0; i < n; ++i)
    if (p.id[i] < 0)
      ctx.fail("particle with negative id " + std::to_string(p.id[i]));
  for (std::size_t k = 0; k < c.contacts.size(); ++k) {
    const auto& key = c.contacts.key(k);
    if (key.first < 0 || key.first >= key.second)
      ctx.fail("contact key (" + std::to_string(key.first) + ", " + std::to_string(key.second) +
               ") is not (first < second, both >= 0)");
  }
  if (c.network) {
    const auto& f = *c.network;
    for (const auto* v : {&f.normal_force, &f.tangential_magnitude, &f.mobilisation, &f.strong})
      if (v->size() != c.contacts.size())
        ctx.fail("a per-contact /network array has " + std::to_string(v->size()) + " rows for " +
                 std::to_string(c.contacts.size()) + " contacts");
    std::vector<const std::vector<double>*> per_grain = {
        &f.contacts,   &f.carrying_contacts, &f.mean_stress,  &f.rattler,
        &f.bond_order, &f.crystalline,       &f.fixed_rattler};
    if (f.cluster_id.size() != n)
      ctx.fail("/network/cluster_id has " + std::to_string(f.cluster_id.size()) + " rows for " +
               std::to_string(n) + " owned particles");
    for (const auto& v : f.net_force)
      per_grain.push_back(&v);
    for (const auto& v : f.net_moment)
      per_grain.push_back(&v);
    for (const auto& v : f.stress)
      per_grain.push_back(&v);
    for (const auto* v : per_grain)
      if (v->size() != n)
        ctx.fail("a per-grain /network array has " + std::to_string(v->size()) + " rows for " +
                 std::to_string(n) + " owned particles");
  }
  if (!c.meta.kind.empty() && c.meta.kind != "configuration" && c.meta.kind != "checkpoint")
    ctx.fail("kind '" + c.meta.kind + "' is neither 'configuration' nor 'checkpoint'");
  for (int a = 0; a < dim; ++a)
    if (!(c.cell.length[a] > 0) || !std::isfinite(c.cell.length[a]))
      ctx.fail("cell length has a non-positive or non-finite component");
}

template <int dim, class Phase>
void write_contents(MPI_Comm comm, const FileContext& ctx, hid_t file, hid_t dxpl,
                    const Configuration<dim>& c, const Slice& ps, const Slice& cs, Phase&& phase);

/// Collective: writes the whole file at `temp` (closed on return or on throw).
///
/// Failure is collective too. A write can fail on one rank only (disk full, quota, EFBIG:
/// MPI-IO reports the error on the rank whose write failed); that rank would leave, close the
/// file (a collective H5Fclose) while the others enter the next collective write, and both
/// would wait forever (issue 31: one rank in H5Fclose -> MPI_Barrier, the other in H5Dwrite ->
/// MPI_Allreduce). So every phase below ends with an agreement (collectively(): an all-reduce
/// of the outcome); on a failure every rank throws the same error at the same point, and the
/// handles close in the same order everywhere.
template <int dim>
void write_file(MPI_Comm comm, const FileContext& ctx, const Configuration<dim>& c, const Slice& ps,
                const Slice& cs) {
  auto phase = [comm](auto&& f) { collectively(comm, f); };
  Handle fapl, file, dxpl;
  phase([&] {
    fapl = mpio_fapl(ctx, comm);
    file = h5::file_handle(
        ctx.id(H5Fcreate(ctx.path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl), "cannot create"));
    dxpl = collective_dxpl(ctx);
  });

  try {
    write_contents(comm, ctx, file, dxpl, c, ps, cs, phase);
    dxpl.reset();
    // The flush writes HDF5's metadata: the last write, which can fail alone too. Done apart
    // from the close, so that a failure leaves the file object intact (below).
    phase([&] { ctx.rc(H5Fflush(file, H5F_SCOPE_LOCAL), "cannot flush the file"); });
  } catch (...) {
    // After a failed write, HDF5 1.10.8 cannot close the file (the close flushes again and
    // fails, leaving a half-destroyed file object); its shutdown at MPI_Finalize would then
    // segfault in H5F__close_cb, so the process ends without it (drivers/main.cpp, exit code
    // 74). Closing here would not help: leave the file to the process's end. The temporary
    // file is removed by the caller.
    (void)file.release();
    file_left_open() = true;
    throw;
  }
  phase([&] {
    if (!file.reset())
      ctx.fail("cannot close the file", true);
  });
}

/// The /network group (docs/hdf5-schema.md): the contact segments as 2 points per contact and
/// a line per contact, their forces and class, and the per-grain sums; for the XDMF sidecar.
template <int dim, class Phase>
void write_network(const FileContext& ctx, hid_t file, hid_t dxpl, const NetworkFields<dim>& f,
                   const Slice& ps, const Slice& cs, Phase&& phase) {
  const std::size_t nc = static_cast<std::size_t>(cs.count);
  Handle g;
  phase([&] { g = group_create(ctx, file, "network"); });
  const std::string gn = "/network";
  auto rows = [&](const char* name, const auto& values, const Slice& slice, int cols,
                  const char* unit) {
    phase([&] { write_rows(ctx, g, gn, name, values, slice, cols, unit, dxpl); });
  };
  std::vector<double> point;
  point.reserve(2 * nc * dim);
  std::vector<std::int64_t> line(2 * nc);
  for (std::size_t k = 0; k < nc; ++k) {
    for (const auto* v : {&f.start[k], &f.end[k]})
      for (int a = 0; a < dim; ++a)
        point.push_back((*v)[a]);
    line[2 * k] = 2 * (cs.offset + static_cast<std::int64_t>(k));
    line[2 * k + 1] = line[2 * k] + 1;
  }
  rows("point", point, Slice{2 * cs.global, 2 * cs.offset, 2 * cs.count}, dim, "m");
  rows("line", line, cs, 2, "1");
  rows("normal_force", f.normal_force, cs, 0, "N");
  rows("tangential_force", f.tangential_magnitude, cs, 0, "N");
  rows("kind", f.kind, cs, 0, "1");
  rows("mobilisation", f.mobilisation, cs, 0, "1");
  rows("strong", f.strong, cs, 0, "1");
  rows("contacts", f.contacts, ps, 0, "1");
  rows("carrying_contacts", f.carrying_contacts, ps, 0, "1");
  rows("mean_stress", f.mean_stress, ps, 0, "Pa");
  rows("rattler", f.rattler, ps, 0, "1");
  rows("fixed_rattler", f.fixed_rattler, ps, 0, "1");
  rows("cluster_id", f.cluster_id, ps, 0, "1");
  rows("bond_order", f.bond_order, ps, 0, "1");
  rows("crystalline", f.crystalline, ps, 0, "1");
  std::vector<double> net;
  net.reserve(static_cast<std::size_t>(ps.count) * dim);
  for (std::int64_t i = 0; i < ps.count; ++i)
    for (int a = 0; a < dim; ++a)
      net.push_back(f.net_force[a][static_cast<std::size_t>(i)]);
  rows("net_force", net, ps, dim, "N");
  // [n, rot_dim], as /particles/angular_velocity: about z in 2D, (x, y, z) in 3D.
  constexpr int rd = rot_dim<dim>;
  std::vector<double> moment;
  moment.reserve(static_cast<std::size_t>(ps.count) * rd);
  for (std::int64_t i = 0; i < ps.count; ++i)
    for (int a = 0; a < rd; ++a)
      moment.push_back(f.net_moment[std::size_t(a)][static_cast<std::size_t>(i)]);
  rows("net_moment", moment, ps, rd, "N m");
  // [n, dim * dim], row-major sigma_ab: the sidecar shows it as a tensor (3D) or a
  // 4-component matrix (2D: ParaView has no 2 x 2 tensor).
  std::vector<double> stress;
  stress.reserve(static_cast<std::size_t>(ps.count) * dim * dim);
  for (std::int64_t i = 0; i < ps.count; ++i)
    for (const auto& c : f.stress)
      stress.push_back(c[static_cast<std::size_t>(i)]);
  rows("stress", stress, ps, dim * dim, "Pa");
}

/// write_file's datasets and attributes, each phase agreed on by every rank.
template <int dim, class Phase>
void write_contents(MPI_Comm comm, const FileContext& ctx, hid_t file, hid_t dxpl,
                    const Configuration<dim>& c, const Slice& ps, const Slice& cs, Phase&& phase) {
  constexpr int rd = rot_dim<dim>, od = orient_dim<dim>;
  // Root attributes (collective metadata: every rank passes the same values).
  const FileMeta& m = c.meta;
  phase([&] {
    write_attribute(ctx, file, "format", std::string("granpack"));
    write_attribute(ctx, file, "format_version", kHdf5FormatVersion);
    write_attribute(ctx, file, "granpack_version",
                    m.granpack_version.empty() ? std::string(GRANPACK_VERSION)
                                               : m.granpack_version);
    write_attribute(ctx, file, "dimension", dim);
    write_attribute(ctx, file, "n_particles", ps.global);
    write_attribute(ctx, file, "n_contacts", cs.global);
    write_attribute(ctx, file, "time", m.time);
    write_attribute(ctx, file, "step", m.step);
    write_attribute(ctx, file, "stage_index", m.stage_index);
    write_attribute(ctx, file, "stage_name", m.stage_name);
    write_attribute(ctx, file, "kind", m.kind.empty() ? std::string("configuration") : m.kind);
  });

  // /deck (and /run_state in checkpoints): scalar fixed-length strings, written by rank 0.
  phase([&] { write_text_dataset(ctx, file, comm, "deck", m.deck_text); });
  if (!m.run_state.empty())
    phase([&] { write_text_dataset(ctx, file, comm, "run_state", m.run_state); });
  if (m.parameters)
    phase([&] { write_parameters(ctx, file, *m.parameters, dim); });

  {
    Handle g;
    phase([&] { g = group_create(ctx, file, "cell"); });
    const Slice whole{dim, 0, rank_of(comm) == 0 ? dim : 0};
    std::vector<double> length(c.cell.length.data(), c.cell.length.data() + dim);
    std::vector<double> rate(c.cell.rate.data(), c.cell.rate.data() + dim);
    phase([&] { write_rows(ctx, g, "/cell", "length", length, whole, 0, "m", dxpl); });
    phase([&] { write_rows(ctx, g, "/cell", "rate", rate, whole, 0, "m/s", dxpl); });
  }

  {
    const auto& p = c.particles;
    const std::size_t n = static_cast<std::size_t>(ps.count);
    Handle g;
    phase([&] { g = group_create(ctx, file, "particles"); });
    const std::string gn = "/particles";
    // rows(NAME, VALUES, COLS, UNIT): one dataset of this group, agreed on by every rank.
    auto rows = [&](const char* name, const auto& values, int cols, const char* unit) {
      phase([&] { write_rows(ctx, g, gn, name, values, ps, cols, unit, dxpl); });
    };
    rows("id", std::vector<std::int64_t>(p.id.begin(), p.id.begin() + n), 0, "1");
    rows("radius", std::vector<double>(p.radius.begin(), p.radius.begin() + n), 0, "m");
    rows("mass", std::vector<double>(p.mass.begin(), p.mass.begin() + n), 0, "kg");
    rows("inertia", std::vector<double>(p.inertia.begin(), p.inertia.begin() + n), 0, "kg m^2");
    rows("scaled_position", flatten(p.position, n), dim, "1");
    std::vector<Vec<dim>> real(n);
    for (std::size_t i = 0; i < n; ++i)
      real[i] = c.cell.to_real(p.position[i]);
    rows("position", flatten(real, n), dim, "m");
    rows("velocity", flatten(p.velocity, n), dim, "m/s");
    rows("angular_velocity", flatten(p.angular_velocity, n), rd, "rad/s");
    rows("orientation", flatten(p.orientation, n), od, dim == 2 ? "rad" : "1");
  }
  phase([] { run_write_hook("after_particles"); }); // tests: a failure on some ranks only
  if (m.kind == "checkpoint")
    fault_point(FaultPoint::kCheckpointDatasets);

  {
    const auto& cst = c.contacts;
    const std::size_t nc = cst.size();
    Handle g;
    phase([&] { g = group_create(ctx, file, "contacts"); });
    const std::string gn = "/contacts";
    std::vector<std::int64_t> first(nc), second(nc), age(nc);
    std::vector<double> normal(nc), tangential, rolling;
    std::vector<std::uint32_t> flags(nc);
    tangential.reserve(nc * dim);
    rolling.reserve(nc * rd);
    for (std::size_t k = 0; k < nc; ++k) {
      const auto& s = cst.state(k);
      first[k] = cst.key(k).first;
      second[k] = cst.key(k).second;
      normal[k] = s.normal_force;
      for (int a = 0; a < dim; ++a)
        tangential.push_back(s.tangential_force[a]);
      for (int a = 0; a < rd; ++a)
        rolling.push_back(s.rolling[a]);
      flags[k] = s.flags;
      age[k] = s.age;
    }
    auto rows = [&](const char* name, const auto& values, int cols, const char* unit) {
      phase([&] { write_rows(ctx, g, gn, name, values, cs, cols, unit, dxpl); });
    };
    rows("first", first, 0, "1");
    rows("second", second, 0, "1");
    rows("normal_force", normal, 0, "N");
    rows("tangential_force", tangential, dim, "N");
    rows("rolling", rolling, rd, "rad");
    rows("flags", flags, 0, "1");
    rows("age", age, 0, "steps");
  }
  if (c.network)
    write_network(ctx, file, dxpl, *c.network, ps, cs, phase);
}

/// Why a write into `file` most likely failed: HDF5 and MPI-IO report "file write failed"
/// without the errno (Open MPI prints it on stderr, apart from our message). Looked up while
/// the temporary file still takes its space: the file system nearly full, or a file size
/// limit (ulimit -f); neither: most likely a disk quota (EDQUOT, which statvfs does not see:
/// quotas are per user or project), said so with how to check it.
std::string likely_write_cause(const std::filesystem::path& file) {
  const auto dir = file.parent_path().empty() ? std::filesystem::path(".") : file.parent_path();
  struct statvfs v {};
  if (::statvfs(dir.c_str(), &v) == 0) {
    const unsigned long long free_bytes = static_cast<unsigned long long>(v.f_bavail) * v.f_frsize;
    if (free_bytes < (1ULL << 20))
      return "No space left on device (" + std::to_string(free_bytes / 1024) + " kB free in " +
             dir.string() + ")";
  }
  struct rlimit r {};
  if (::getrlimit(RLIMIT_FSIZE, &r) == 0 && r.rlim_cur != RLIM_INFINITY)
    return "File too large (a file size limit, ulimit -f, of " +
           std::to_string(static_cast<unsigned long long>(r.rlim_cur)) + " bytes)";
  return "not a full disk nor a file size limit: most likely a disk quota (Disk quota exceeded, "
         "EDQUOT; check with `quota -s` or the cluster's quota tool), else an I/O error of the "
         "file system";
}

/// Collective. The message of a failed write (exit code 74, docs/long-jobs.md): the file, the
/// cause, and what is left on disk (the temporary file removed, a previous file untouched).
/// Removes the temporary file (rank 0), after looking up the likely cause.
std::string fail_write(MPI_Comm comm, const std::filesystem::path& path,
                       const std::filesystem::path& temp, const std::string& error) {
  std::string cause;
  if (rank_of(comm) == 0) {
    cause = likely_write_cause(temp);
    std::error_code ec;
    std::filesystem::remove(temp, ec);
  }
  broadcast_string(comm, cause); // also the barrier: the temporary file is gone
  std::error_code ec;
  const bool previous = std::filesystem::exists(path, ec);
  return "cannot write " + path.string() + ": " + (cause.empty() ? "" : cause + ": ") + error +
         "; " + temp.filename().string() + " was removed" +
         (previous ? ", the previous " + path.filename().string() + " is unchanged"
                   : std::string());
}

/// Collective. This rank's slices of the particle and contact rows of a write: offsets by
/// exclusive prefix sums of the owned counts.
template <int dim>
std::pair<Slice, Slice> write_slices(MPI_Comm comm, const Configuration<dim>& c) {
  std::int64_t local[2] = {static_cast<std::int64_t>(c.particles.n_owned()),
                           static_cast<std::int64_t>(c.contacts.size())};
  std::int64_t offset[2] = {0, 0}, total[2] = {0, 0};
  exclusive_prefix_sum(comm, local, offset);
  global_sum(comm, local, total);
  return {Slice{total[0], offset[0], local[0]}, Slice{total[1], offset[1], local[1]}};
}

/// This rank's rows [n*r/P, n*(r+1)/P) of n.
Slice even_slice(std::int64_t n, int rank, int size) {
  const std::int64_t lo = n * rank / size, hi = n * (rank + 1) / size;
  return {n, lo, hi - lo};
}

} // namespace

bool hdf5_file_left_open() {
  return file_left_open();
}

namespace detail {
void set_hdf5_write_hook(std::function<void(std::string_view)> hook) {
  write_hook() = std::move(hook);
}
} // namespace detail

template <int dim>
void write_configuration(MPI_Comm comm, const std::filesystem::path& path,
                         const Configuration<dim>& c) {
  h5::silence_errors();
  const int rank = rank_of(comm);
  const FileContext target{path, false};
  const FileContext temp{temp_path_for(path), false};
  collectively(comm, [&] { validate_for_write(c, target); });

  const auto [ps, cs] = write_slices(comm, c);

  CollectiveError err;
  try {
    write_file(comm, temp, c, ps, cs);
    run_write_hook("before_rename");
  } catch (const Error& e) {
    err.record(e.what(), e.exit_code());
  } catch (const std::exception& e) {
    err.record(temp.path.string() + ": " + e.what());
  }
  try {
    err.raise_if_any(comm); // also the barrier: every rank has closed the file
  } catch (const Error& e) {
    throw WriteError(fail_write(comm, path, temp.path, e.what()));
  }
  if (c.meta.kind == "checkpoint")
    fault_point(FaultPoint::kCheckpointRename);
  std::string failed;
  if (rank == 0) {
    try {
      commit_temp_file(temp.path, path);
    } catch (const Error& e) {
      failed = e.what();
    }
  }
  broadcast_string(comm, failed);
  if (!failed.empty())
    throw WriteError(fail_write(comm, path, temp.path, failed));
  collectively(comm, [&] {
    if (rank != 0)
      return;
    XdmfParticles x{path.filename().string(),   dim, ps.global, c.meta.time,
                    c.network ? cs.global : -1, {}};
    write_particles_xdmf(xdmf_path_for(path), x);
  });
}

template <int dim>
Configuration<dim> read_configuration(MPI_Comm comm, const std::filesystem::path& path) {
  constexpr int rd = rot_dim<dim>, od = orient_dim<dim>;
  const FileContext ctx{path, true};
  auto file = open_for_reading(comm, ctx);
  const int rank = rank_of(comm), size = size_of(comm);

  Configuration<dim> c;
  Handle pg, cg;
  // Particle datasets, then contact datasets, in a fixed order.
  struct Entry {
    const char* name;
    bool particle;
    int cols;
    Handle dset;
  };
  std::vector<Entry> entries;
  // Metadata and shapes first (independent reads): a bad file fails here on every rank,
  // before any collective data transfer.
  collectively_typed(comm, [&] {
    c.meta = read_meta(ctx, file);
    if (c.meta.dimension != dim)
      ctx.fail("holds a " + std::to_string(c.meta.dimension) + "-D configuration, expected " +
               std::to_string(dim) + "-D");
    c.cell = read_cell<dim>(ctx, file);
    pg = group_open(ctx, file, "particles");
    cg = group_open(ctx, file, "contacts");
    const std::int64_t n = c.meta.n_particles, nc = c.meta.n_contacts;
    auto add = [&]<class T>(const char* name, bool particle, int cols, T) {
      entries.push_back(
          {name, particle, cols,
           open_rows<T>(ctx, particle ? pg.get() : cg.get(), particle ? "/particles" : "/contacts",
                        name, particle ? n : nc, cols)});
    };
    add("id", true, 0, std::int64_t{});
    add("radius", true, 0, double{});
    add("mass", true, 0, double{});
    add("inertia", true, 0, double{});
    add("scaled_position", true, dim, double{});
    add("velocity", true, dim, double{});
    add("angular_velocity", true, rd, double{});
    add("orientation", true, od, double{});
    add("first", false, 0, std::int64_t{});
    add("second", false, 0, std::int64_t{});
    add("normal_force", false, 0, double{});
    add("tangential_force", false, dim, double{});
    add("rolling", false, rd, double{});
    add("flags", false, 0, std::uint32_t{});
    add("age", false, 0, std::int64_t{});
  });

  const Slice ps = even_slice(c.meta.n_particles, rank, size);
  const Slice cs = even_slice(c.meta.n_contacts, rank, size);
  std::vector<std::int64_t> ids, firsts, seconds; // for the global id checks below
  collectively_typed(comm, [&] {
    auto dxpl = collective_dxpl(ctx);
    auto what = [](const Entry& e) {
      return std::string(e.particle ? "/particles/" : "/contacts/") + e.name;
    };
    auto f64 = [&](int k) {
      const auto& e = entries[k];
      return read_rows<double>(ctx, e.dset, what(e), e.particle ? ps : cs, e.cols, dxpl);
    };
    auto i64 = [&](int k) {
      const auto& e = entries[k];
      return read_rows<std::int64_t>(ctx, e.dset, what(e), e.particle ? ps : cs, e.cols, dxpl);
    };
    const auto id = i64(0);
    const auto radius = f64(1), mass = f64(2), inertia = f64(3), spos = f64(4), vel = f64(5),
               omega = f64(6), orient = f64(7);
    const auto first = i64(8), second = i64(9), age = i64(14);
    const auto normal = f64(10), tangential = f64(11), rolling = f64(12);
    const auto flags =
        read_rows<std::uint32_t>(ctx, entries[13].dset, "/contacts/flags", cs, 0, dxpl);
    entries.clear(); // close the datasets before the file

    const auto np = static_cast<std::size_t>(ps.count), nc = static_cast<std::size_t>(cs.count);
    // Values the engine integrates or sums: a NaN or infinity in any of them would only
    // surface later as a blow-up or as nan in an analysis, far from its cause.
    auto all_finite = [&](const std::vector<double>& v, const char* name, const Slice& s,
                          int cols) {
      const std::size_t width = std::max(cols, 1);
      for (std::size_t k = 0; k < v.size(); ++k)
        if (!std::isfinite(v[k]))
          ctx.fail(std::string(name) + " row " + std::to_string(s.offset + k / width) + " holds " +
                   std::to_string(v[k]) + " (need finite values)");
    };
    all_finite(vel, "/particles/velocity", ps, dim);
    all_finite(omega, "/particles/angular_velocity", ps, rd);
    all_finite(orient, "/particles/orientation", ps, od);
    all_finite(normal, "/contacts/normal_force", cs, 0);
    all_finite(tangential, "/contacts/tangential_force", cs, dim);
    all_finite(rolling, "/contacts/rolling", cs, rd);
    for (std::size_t i = 0; i < np; ++i)
      if (!(mass[i] > 0 && inertia[i] > 0) || !std::isfinite(mass[i]) || !std::isfinite(inertia[i]))
        ctx.fail("/particles/mass or /particles/inertia row " + std::to_string(ps.offset + i) +
                 " = " + std::to_string(mass[i]) + ", " + std::to_string(inertia[i]) +
                 " (need positive finite values)");
    for (std::size_t k = 0; k < nc; ++k)
      if (normal[k] < 0)
        ctx.fail("/contacts/normal_force row " + std::to_string(cs.offset + k) + " = " +
                 std::to_string(normal[k]) +
                 " (the elastic normal force N^e is never negative; "
                 "docs/hdf5-schema.md)");
    ids = id, firsts = first, seconds = second;
    c.particles.reserve(np);
    for (std::size_t i = 0; i < np; ++i) {
      Particle<dim> q;
      q.id = id[i];
      if (q.id < 0)
        ctx.fail("/particles/id row " + std::to_string(ps.offset + i) + " is negative");
      q.radius = radius[i];
      q.mass = mass[i];
      q.inertia = inertia[i];
      q.position = row<Vec<dim>>(spos, i);
      q.velocity = row<Vec<dim>>(vel, i);
      q.angular_velocity = row<RotVec<dim>>(omega, i);
      q.orientation = row<OrientVec<dim>>(orient, i);
      // What the rest of the code bins grains by: a NaN or far-away scaled position (cast to
      // a cell index: undefined behaviour) or a non-positive radius (neighbour grid sizes).
      // Positions between rebuilds may stray a little outside [0, 1), never a cell away.
      if (!(q.radius > 0) || !std::isfinite(q.radius))
        ctx.fail("/particles/radius row " + std::to_string(ps.offset + i) + " = " +
                 std::to_string(q.radius) + " (need a positive finite radius)");
      for (int a = 0; a < dim; ++a)
        if (!(q.position[a] > -1.0 && q.position[a] < 2.0))
          ctx.fail("/particles/scaled_position row " + std::to_string(ps.offset + i) + " = " +
                   std::to_string(q.position[a]) + " (need a finite scaled position near [0, 1))");
      c.particles.add_owned(q);
    }
    for (std::size_t k = 0; k < nc; ++k) {
      if (first[k] < 0 || first[k] >= second[k])
        ctx.fail("/contacts row " + std::to_string(cs.offset + k) +
                 " has first = " + std::to_string(first[k]) +
                 ", second = " + std::to_string(second[k]) + " (need 0 <= first < second)");
      ContactState<dim> s;
      s.normal_force = normal[k];
      s.tangential_force = row<Vec<dim>>(tangential, k);
      s.rolling = row<RotVec<dim>>(rolling, k);
      s.flags = flags[k];
      s.age = age[k];
      c.contacts.insert({first[k], second[k]}, s);
    }
    if (c.contacts.size() != nc)
      ctx.fail("/contacts holds duplicate keys");
  });
  // Across the ranks' slices (every rank gets the same verdict, so all throw together).
  if (const std::string bad = find_id_inconsistency(comm, ids, firsts, seconds); !bad.empty())
    ctx.fail(bad);
  return c;
}

FileMeta read_file_meta(MPI_Comm comm, const std::filesystem::path& path) {
  const FileContext ctx{path, true};
  auto file = open_for_reading(comm, ctx);
  FileMeta m;
  collectively_typed(comm, [&] { m = read_meta(ctx, file); });
  return m;
}

std::vector<std::int64_t> read_fixed_rattlers(MPI_Comm comm, const std::filesystem::path& path) {
  const FileContext ctx{path, true};
  auto file = open_for_reading(comm, ctx);
  // Each step of the path looked up alone: a missing /network is no error (older files,
  // checkpoints), and H5Lexists of "network/fixed_rattler" would fail on it.
  auto exists = [&](hid_t where, const char* name, const std::string& what) {
    const htri_t e = H5Lexists(where, name, H5P_DEFAULT);
    if (e < 0)
      ctx.fail("cannot look up " + what, true);
    return e > 0;
  };
  FileMeta meta;
  Handle ids, flags;
  collectively_typed(comm, [&] {
    meta = read_meta(ctx, file);
    if (!exists(file, "network", "group /network"))
      return;
    auto ng = group_open(ctx, file, "network");
    if (!exists(ng, "fixed_rattler", "dataset /network/fixed_rattler"))
      return;
    auto pg = group_open(ctx, file, "particles");
    ids = open_rows<std::int64_t>(ctx, pg, "/particles", "id", meta.n_particles, 0);
    flags = open_rows<double>(ctx, ng, "/network", "fixed_rattler", meta.n_particles, 0);
  });
  if (!flags.valid()) // the same on every rank: one file
    return {};
  const Slice ps = even_slice(meta.n_particles, rank_of(comm), size_of(comm));
  std::vector<std::int64_t> mine;
  collectively_typed(comm, [&] {
    auto dxpl = collective_dxpl(ctx);
    const auto id = read_rows<std::int64_t>(ctx, ids, "/particles/id", ps, 0, dxpl);
    const auto flag = read_rows<double>(ctx, flags, "/network/fixed_rattler", ps, 0, dxpl);
    ids.reset(); // close the datasets before the file
    flags.reset();
    for (std::size_t i = 0; i < flag.size(); ++i) {
      if (flag[i] != 0.0 && flag[i] != 1.0)
        ctx.fail("/network/fixed_rattler row " + std::to_string(ps.offset + std::int64_t(i)) +
                 " = " + std::to_string(flag[i]) + " (a flag: 0 or 1)");
      if (flag[i] == 1.0)
        mine.push_back(id[i]);
    }
  });
  std::vector<std::int64_t> all = allgather_concat(comm, mine);
  std::sort(all.begin(), all.end());
  return all;
}

std::string describe_file(MPI_Comm comm, const std::filesystem::path& path) {
  const FileContext ctx{path, true};
  auto file = open_for_reading(comm, ctx);
  FileMeta m;
  std::vector<double> length, rate;
  collectively_typed(comm, [&] {
    m = read_meta(ctx, file);
    auto to_vec = [](const auto& v) { return std::vector<double>(v.data(), v.data() + v.size()); };
    if (m.dimension == 2) {
      auto cell = read_cell<2>(ctx, file);
      length = to_vec(cell.length), rate = to_vec(cell.rate);
    } else {
      auto cell = read_cell<3>(ctx, file);
      length = to_vec(cell.length), rate = to_vec(cell.rate);
    }
  });
  auto join = [](const std::vector<double>& v, const char* sep) {
    std::ostringstream os;
    os.precision(10);
    for (std::size_t a = 0; a < v.size(); ++a)
      os << (a ? sep : "") << v[a];
    return os.str();
  };
  std::ostringstream os;
  os.precision(10);
  os << "file:        " << path.string() << "\n"
     << "kind:        " << m.kind << " (written by granpack " << m.granpack_version << ")\n"
     << "dimension:   " << m.dimension << "\n"
     << "particles:   " << m.n_particles << "\n"
     << "contacts:    " << m.n_contacts << "\n"
     << "cell:        L = " << join(length, " x ") << " m, dL/dt = (" << join(rate, ", ")
     << ") m/s\n"
     << "time:        " << m.time << " s (step " << m.step << ")\n"
     << "stage:       " << m.stage_index << (m.stage_name.empty() ? "" : " '" + m.stage_name + "'")
     << "\n"
     << "deck:        " << m.deck_text.size() << " bytes\n";
  return os.str();
}

// ----------------------------------------------------------------------------------------
// Trajectories: one file, a snapshot per group /snapshots/<step>

std::string snapshot_group(std::int64_t step) {
  char name[40];
  std::snprintf(name, sizeof name, "/snapshots/%012lld", static_cast<long long>(step));
  return name;
}

namespace {
/// Rank 0 alone, the file closed on every rank: `f(file)` on the trajectory opened serially
/// (read-write or read-only); the outcome is agreed on by every rank (Error on every rank).
template <class F>
void on_rank0_serially(MPI_Comm comm, const FileContext& ctx, bool write, F&& f) {
  collectively(comm, [&] {
    if (rank_of(comm) != 0)
      return;
    h5::silence_errors();
    auto file = h5::file_handle(
        ctx.id(H5Fopen(ctx.path.c_str(), write ? H5F_ACC_RDWR : H5F_ACC_RDONLY, H5P_DEFAULT),
               "cannot open the trajectory"));
    f(file);
    if (!file.reset())
      ctx.fail("cannot close the trajectory", true);
  });
}

/// The snapshots of an open trajectory, in the order of their names (= steps).
std::vector<TrajectorySnapshot> snapshot_index(const FileContext& ctx, hid_t file) {
  std::vector<TrajectorySnapshot> out;
  if (H5Lexists(file, "snapshots", H5P_DEFAULT) <= 0)
    return out;
  auto g = group_open(ctx, file, "snapshots");
  std::vector<std::string> names;
  auto collect = [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
    static_cast<std::vector<std::string>*>(data)->push_back(name);
    return 0;
  };
  ctx.rc(H5Literate(g, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect, &names),
         "cannot list /snapshots");
  for (const auto& name : names) {
    const std::string where = "/snapshots/" + name + "/";
    auto s = h5::group_handle(
        ctx.id(H5Gopen2(g, name.c_str(), H5P_DEFAULT), "cannot open group " + where));
    TrajectorySnapshot t;
    t.group = "/snapshots/" + name;
    t.step = read_attribute<std::int64_t>(ctx, s, where, "step");
    t.time = read_attribute<double>(ctx, s, where, "time");
    t.n_particles = read_attribute<std::int64_t>(ctx, s, where, "n_particles");
    t.n_contacts = read_attribute<std::int64_t>(ctx, s, where, "n_contacts");
    t.network = H5Lexists(s, "network", H5P_DEFAULT) > 0;
    out.push_back(t);
  }
  return out;
}
} // namespace

template <int dim>
void append_snapshot(MPI_Comm comm, const std::filesystem::path& path, const Configuration<dim>& c,
                     const std::string& deck_text) {
  h5::silence_errors();
  const FileContext ctx{path, false};
  collectively(comm, [&] { validate_for_write(c, ctx); });
  const auto [ps, cs] = write_slices(comm, c);
  int exists = 0;
  if (rank_of(comm) == 0)
    exists = std::filesystem::exists(path) ? 1 : 0;
  exists = broadcast_value<int>(comm, exists);
  const std::string name = snapshot_group(c.meta.step);

  auto phase = [comm](auto&& f) { collectively(comm, f); };
  Handle fapl, file, dxpl;
  try {
    phase([&] {
      fapl = mpio_fapl(ctx, comm);
      file = h5::file_handle(
          exists
              ? ctx.id(H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl), "cannot open for appending")
              : ctx.id(H5Fcreate(path.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, fapl), "cannot create"));
      dxpl = collective_dxpl(ctx);
    });
    if (!exists) {
      phase([&] {
        write_attribute(ctx, file, "format", std::string("granpack"));
        write_attribute(ctx, file, "format_version", kHdf5FormatVersion);
        write_attribute(ctx, file, "granpack_version", std::string(GRANPACK_VERSION));
        write_attribute(ctx, file, "dimension", dim);
        write_attribute(ctx, file, "kind", std::string("trajectory"));
      });
      phase([&] { write_text_dataset(ctx, file, comm, "deck", deck_text); });
      phase([&] { group_create(ctx, file, "snapshots"); });
    }
    Handle g;
    phase([&] {
      if (H5Lexists(file, name.c_str(), H5P_DEFAULT) > 0)
        ctx.fail("already holds a snapshot at step " + std::to_string(c.meta.step));
      g = group_create(ctx, file, name.c_str());
    });
    write_contents(comm, ctx, g, dxpl, c, ps, cs, phase);
    g.reset();
    dxpl.reset();
    phase([&] { ctx.rc(H5Fflush(file, H5F_SCOPE_LOCAL), "cannot flush the file"); });
  } catch (const Error& e) {
    if (file.valid()) {
      (void)file.release(); // as write_file: HDF5 1.10.8 cannot close after a failed write
      file_left_open() = true;
    }
    throw WriteError("cannot append the snapshot of step " + std::to_string(c.meta.step) + " to " +
                     path.string() + ": " + e.what());
  }
  phase([&] {
    if (!file.reset())
      ctx.fail("cannot close the file", true);
  });
}

std::vector<TrajectorySnapshot> read_trajectory_index(MPI_Comm comm,
                                                      const std::filesystem::path& path) {
  const FileContext ctx{path, false};
  std::vector<TrajectorySnapshot> index;
  on_rank0_serially(comm, ctx, false, [&](hid_t file) { index = snapshot_index(ctx, file); });
  return index; // complete on rank 0 only
}

void prune_trajectory(MPI_Comm comm, const std::filesystem::path& path, std::int64_t after_step) {
  int exists = 0;
  if (rank_of(comm) == 0)
    exists = std::filesystem::exists(path) ? 1 : 0;
  if (!broadcast_value<int>(comm, exists))
    return;
  const FileContext ctx{path, false};
  on_rank0_serially(comm, ctx, true, [&](hid_t file) {
    for (const auto& s : snapshot_index(ctx, file))
      if (s.step > after_step)
        ctx.rc(H5Ldelete(file, s.group.c_str(), H5P_DEFAULT), "cannot delete " + s.group);
  });
}

template void write_configuration<2>(MPI_Comm, const std::filesystem::path&,
                                     const Configuration<2>&);
template void write_configuration<3>(MPI_Comm, const std::filesystem::path&,
                                     const Configuration<3>&);
template Configuration<2> read_configuration<2>(MPI_Comm, const std::filesystem::path&);
template Configuration<3> read_configuration<3>(MPI_Comm, const std::filesystem::path&);
template void append_snapshot<2>(MPI_Comm, const std::filesystem::path&, const Configuration<2>&,
                                 const std::string&);
template void append_snapshot<3>(MPI_Comm, const std::filesystem::path&, const Configuration<3>&,
                                 const std::string&);

} // namespace granpack
