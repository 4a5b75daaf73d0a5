#include "granpack/io/json_hdf5.h"

#include <algorithm>
#include <vector>

#include "granpack/core/error.h"
#include "granpack/io/atomic_file.h"
#include "granpack/io/hdf5_handle.h"

namespace granpack {

namespace {

struct Writer {
  std::filesystem::path file;

  hid_t check(hid_t id, const std::string& what) const {
    if (id < 0)
      throw Error("cannot write " + file.string() + ": " + what + " (" + h5::last_error_detail() +
                  ")");
    return id;
  }
  void check_rc(herr_t rc, const std::string& what) const { check(rc < 0 ? -1 : 0, what); }

  static std::string name_of(std::string key) {
    std::replace(key.begin(), key.end(), '/', '_');
    return key.empty() ? std::string("_") : key;
  }
  static bool numbers(const nlohmann::json& a) {
    return a.is_array() && !a.empty() &&
           std::all_of(a.begin(), a.end(), [](const auto& x) { return x.is_number(); });
  }
  static bool matrix(const nlohmann::json& a) {
    return a.is_array() && !a.empty() && numbers(a[0]) &&
           std::all_of(a.begin(), a.end(),
                       [&](const auto& r) { return numbers(r) && r.size() == a[0].size(); });
  }

  void dataset(hid_t group, const std::string& name, const std::vector<double>& v,
               std::vector<hsize_t> dims, const std::string& path) const {
    auto space =
        h5::dataspace_handle(check(H5Screate_simple(int(dims.size()), dims.data(), nullptr), path));
    auto d = h5::dataset_handle(check(H5Dcreate2(group, name.c_str(), H5T_IEEE_F64LE, space,
                                                 H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                                      path));
    check_rc(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), path);
  }

  void attribute(hid_t group, const std::string& name, const nlohmann::json& x,
                 const std::string& path) const {
    auto space = h5::dataspace_handle(check(H5Screate(H5S_SCALAR), path));
    if (x.is_string()) {
      const std::string s = x.get<std::string>();
      auto type = h5::datatype_handle(check(H5Tcopy(H5T_C_S1), path));
      check_rc(H5Tset_size(type, H5T_VARIABLE), path);
      check_rc(H5Tset_cset(type, H5T_CSET_UTF8), path);
      auto a = h5::attribute_handle(
          check(H5Acreate2(group, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), path));
      const char* p = s.c_str();
      check_rc(H5Awrite(a, type, &p), path);
    } else if (x.is_boolean() || x.is_number_integer()) {
      const long long v = x.is_boolean() ? (x.get<bool>() ? 1 : 0) : x.get<long long>();
      auto a = h5::attribute_handle(check(
          H5Acreate2(group, name.c_str(), H5T_STD_I64LE, space, H5P_DEFAULT, H5P_DEFAULT), path));
      check_rc(H5Awrite(a, H5T_NATIVE_LLONG, &v), path);
    } else {
      const double v = x.get<double>();
      auto a = h5::attribute_handle(check(
          H5Acreate2(group, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT), path));
      check_rc(H5Awrite(a, H5T_NATIVE_DOUBLE, &v), path);
    }
  }

  void object(hid_t group, const nlohmann::json& obj, const std::string& path) const {
    for (const auto& [key, x] : obj.items()) {
      const std::string name = name_of(key), here = path + "/" + name;
      if (x.is_object()) {
        auto g = h5::group_handle(
            check(H5Gcreate2(group, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), here));
        object(g, x, here);
      } else if (numbers(x)) {
        std::vector<double> v;
        for (const auto& e : x)
          v.push_back(e.get<double>());
        dataset(group, name, v, {hsize_t(v.size())}, here);
      } else if (matrix(x)) {
        std::vector<double> v;
        for (const auto& r : x)
          for (const auto& e : r)
            v.push_back(e.get<double>());
        dataset(group, name, v, {hsize_t(x.size()), hsize_t(x[0].size())}, here);
      } else if (x.is_number() || x.is_boolean() || x.is_string()) {
        attribute(group, name, x, here);
      }
      // nulls, empty arrays and mixed arrays have no array form: the JSON keeps them.
    }
  }
};

} // namespace

void write_json_as_hdf5(const std::filesystem::path& path, const nlohmann::json& doc) {
  h5::silence_errors();
  const auto tmp = temp_path_for(path);
  Writer w{path};
  try {
    auto f = h5::file_handle(
        w.check(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), "create"));
    w.object(f, doc, "");
    if (!f.reset())
      throw Error("cannot write " + path.string() + ": close failed");
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec); // nothing half-written stays behind
    throw;
  }
  commit_temp_file(tmp, path);
}

} // namespace granpack
