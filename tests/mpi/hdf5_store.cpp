// The parallel HDF5 store: exact round trips on any rank count, collective errors for bad
// files, atomic replacement of an existing file, the human summary and the XDMF sidecar.
#include "granpack/io/hdf5_store.h"

#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>

#include <algorithm>
#include <bit>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <type_traits>

#include "granpack/io/atomic_file.h"
#include "granpack/io/xdmf.h"
#include "mpi_world.h"
#include "test_paths.h"

using namespace granpack;
namespace fs = std::filesystem;

namespace {

using test::world_rank;
using test::world_size;

/// A scratch directory shared by all ranks; np runs apart (ctest may run them concurrently).
fs::path scratch(const std::string& tag) {
  const std::string full = "hdf5_store_" + tag + "_np" + std::to_string(world_size());
  if (world_rank() == 0)
    granpack::test::scratch_dir(full);
  MPI_Barrier(MPI_COMM_WORLD);
  return granpack::test::scratch_dir(full);
}

bool all_ranks(bool ok) {
  int local = ok ? 1 : 0, global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  return global == 1;
}

std::string file_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}
template <class V> bool same_bits(const V& a, const V& b) {
  for (int k = 0; k < V::SizeAtCompileTime; ++k)
    if (!same_bits(a[k], b[k]))
      return false;
  return true;
}

template <int dim> bool same(const Particle<dim>& a, const Particle<dim>& b) {
  return a.id == b.id && same_bits(a.radius, b.radius) && same_bits(a.mass, b.mass) &&
         same_bits(a.inertia, b.inertia) && same_bits(a.position, b.position) &&
         same_bits(a.velocity, b.velocity) && same_bits(a.angular_velocity, b.angular_velocity) &&
         same_bits(a.orientation, b.orientation);
}
template <int dim> bool same(const ContactState<dim>& a, const ContactState<dim>& b) {
  return same_bits(a.normal_force, b.normal_force) &&
         same_bits(a.tangential_force, b.tangential_force) && same_bits(a.rolling, b.rolling) &&
         a.flags == b.flags && a.age == b.age;
}

/// The whole sample, identical on every rank (same seed).
template <int dim> struct Sample {
  Cell<dim> cell;
  std::vector<Particle<dim>> particles;
  std::vector<std::pair<ContactKey, ContactState<dim>>> contacts;
  FileMeta meta;
};

template <int dim> Sample<dim> random_sample(int n, int nc, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0), s(-1.0, 1.0);
  Sample<dim> out;
  for (int a = 0; a < dim; ++a) {
    out.cell.length[a] = 1.5 + 0.75 * a + 0.125 * (a == 2);
    out.cell.rate[a] = -1e-3 * (a + 1) * u(rng);
  }
  for (int k = 0; k < n; ++k) {
    Particle<dim> p;
    p.id = 3 + 7 * static_cast<GlobalId>(k) + static_cast<GlobalId>(rng() % 5);
    p.radius = 0.01 + 0.01 * u(rng);
    p.mass = u(rng);
    p.inertia = 1e-7 * u(rng);
    for (int a = 0; a < dim; ++a) {
      p.position[a] = u(rng);
      p.velocity[a] = s(rng);
    }
    for (int a = 0; a < rot_dim<dim>; ++a)
      p.angular_velocity[a] = 100 * s(rng);
    for (int a = 0; a < orient_dim<dim>; ++a)
      p.orientation[a] = s(rng);
    out.particles.push_back(p);
  }
  std::set<ContactKey> keys;
  while (static_cast<int>(keys.size()) < nc) {
    auto a = out.particles[rng() % n].id, b = out.particles[rng() % n].id;
    if (a != b)
      keys.insert(ContactKey::of(a, b));
  }
  for (const auto& key : keys) {
    ContactState<dim> st;
    st.normal_force = 10 * u(rng);
    for (int a = 0; a < dim; ++a)
      st.tangential_force[a] = s(rng);
    for (int a = 0; a < rot_dim<dim>; ++a)
      st.rolling[a] = 1e-3 * s(rng);
    st.flags = static_cast<std::uint32_t>(rng());
    st.age = static_cast<std::int64_t>(rng() >> 2);
    out.contacts.emplace_back(key, st);
  }
  std::shuffle(out.contacts.begin(), out.contacts.end(), rng);
  out.meta.time = 1.2345678901234567e-3;
  out.meta.step = 123456789012LL;
  out.meta.stage_index = 3;
  out.meta.stage_name = "compress \"iso\"";
  out.meta.kind = "checkpoint";
  out.meta.deck_text =
      "# deck with \"quotes\", 'single', a tab\tand ünïcode\n[cell]\nlength = [1.5, 2.25]\n"
      "\n[[stage]]\nname = \"compress \\\"iso\\\"\"\n";
  return out;
}

/// This rank's part of the sample: uneven shares (rank r of P gets a share ~ (r+1)^2);
/// with several ranks, the last one owns no contact.
template <int dim> Configuration<dim> my_part(const Sample<dim>& s, bool last_has_contacts) {
  const int r = world_rank(), P = world_size();
  auto bounds = [&](std::size_t n, int rank, bool skip_last) {
    std::vector<std::size_t> w(P);
    for (int q = 0; q < P; ++q)
      w[q] = (skip_last && P > 1 && q == P - 1) ? 0 : (q + 1) * (q + 1);
    std::size_t total = 0, before = 0;
    for (int q = 0; q < P; ++q)
      total += w[q];
    for (int q = 0; q < rank; ++q)
      before += w[q];
    return std::pair{n * before / total, n * (before + w[rank]) / total};
  };
  Configuration<dim> c;
  c.cell = s.cell;
  c.meta = s.meta;
  auto [p0, p1] = bounds(s.particles.size(), r, false);
  for (std::size_t i = p0; i < p1; ++i)
    c.particles.add_owned(s.particles[i]);
  auto [c0, c1] = bounds(s.contacts.size(), r, !last_has_contacts);
  for (std::size_t k = c0; k < c1; ++k)
    c.contacts.insert(s.contacts[k].first, s.contacts[k].second);
  return c;
}

/// Checks what `comm` read against the sample: each rank holds its even slice, every value is
/// bit-identical, and over all ranks of comm every particle and contact appears exactly once.
template <int dim>
void expect_matches(MPI_Comm comm, const Sample<dim>& s, const Configuration<dim>& c) {
  int r = 0, P = 1;
  MPI_Comm_rank(comm, &r);
  MPI_Comm_size(comm, &P);
  const auto n = static_cast<std::int64_t>(s.particles.size());
  const auto nc = static_cast<std::int64_t>(s.contacts.size());
  EXPECT_EQ(static_cast<std::int64_t>(c.particles.n_owned()), n * (r + 1) / P - n * r / P);
  EXPECT_EQ(static_cast<std::int64_t>(c.contacts.size()), nc * (r + 1) / P - nc * r / P);
  EXPECT_EQ(c.particles.n_ghost(), 0u);
  for (int a = 0; a < dim; ++a) {
    EXPECT_TRUE(same_bits(c.cell.length[a], s.cell.length[a]));
    EXPECT_TRUE(same_bits(c.cell.rate[a], s.cell.rate[a]));
  }
  EXPECT_EQ(c.meta.dimension, dim);
  EXPECT_EQ(c.meta.n_particles, n);
  EXPECT_EQ(c.meta.n_contacts, nc);
  EXPECT_TRUE(same_bits(c.meta.time, s.meta.time));
  EXPECT_EQ(c.meta.step, s.meta.step);
  EXPECT_EQ(c.meta.stage_index, s.meta.stage_index);
  EXPECT_EQ(c.meta.stage_name, s.meta.stage_name);
  EXPECT_EQ(c.meta.deck_text, s.meta.deck_text);
  EXPECT_EQ(c.meta.kind, s.meta.kind);
  EXPECT_EQ(c.meta.granpack_version, GRANPACK_VERSION);

  std::map<GlobalId, const Particle<dim>*> by_id;
  for (const auto& p : s.particles)
    by_id[p.id] = &p;
  int bad = 0;
  std::vector<std::int64_t> ids;
  for (std::size_t i = 0; i < c.particles.n_owned(); ++i) {
    const auto p = c.particles.get(i);
    ids.push_back(p.id);
    auto it = by_id.find(p.id);
    if (it == by_id.end() || !same(p, *it->second))
      ++bad;
  }
  EXPECT_EQ(bad, 0) << "particles differing from what was written";
  std::map<ContactKey, const ContactState<dim>*> by_key;
  for (const auto& [k, st] : s.contacts)
    by_key[k] = &st;
  bad = 0;
  std::vector<std::int64_t> keys;
  for (std::size_t k = 0; k < c.contacts.size(); ++k) {
    keys.push_back(c.contacts.key(k).first);
    keys.push_back(c.contacts.key(k).second);
    auto it = by_key.find(c.contacts.key(k));
    if (it == by_key.end() || !same(c.contacts.state(k), *it->second))
      ++bad;
  }
  EXPECT_EQ(bad, 0) << "contacts differing from what was written";

  // Gather, sort and compare with the full lists: each appears exactly once.
  auto gather = [&](const std::vector<std::int64_t>& local) {
    int len = static_cast<int>(local.size());
    std::vector<int> lens(P), displs(P, 0);
    MPI_Allgather(&len, 1, MPI_INT, lens.data(), 1, MPI_INT, comm);
    for (int q = 1; q < P; ++q)
      displs[q] = displs[q - 1] + lens[q - 1];
    std::vector<std::int64_t> all(displs.back() + lens.back());
    MPI_Allgatherv(local.data(), len, MPI_INT64_T, all.data(), lens.data(), displs.data(),
                   MPI_INT64_T, comm);
    return all;
  };
  auto all_ids = gather(ids);
  std::sort(all_ids.begin(), all_ids.end());
  std::vector<std::int64_t> want_ids;
  for (const auto& p : s.particles)
    want_ids.push_back(p.id);
  std::sort(want_ids.begin(), want_ids.end());
  EXPECT_EQ(all_ids, want_ids);
  auto flat = gather(keys);
  std::vector<ContactKey> all_keys, want_keys;
  for (std::size_t k = 0; k + 1 < flat.size(); k += 2)
    all_keys.push_back({flat[k], flat[k + 1]});
  for (const auto& kv : s.contacts)
    want_keys.push_back(kv.first);
  std::sort(all_keys.begin(), all_keys.end());
  std::sort(want_keys.begin(), want_keys.end());
  EXPECT_TRUE(all_keys == want_keys);
}

/// Runs f on every rank and expects InputError everywhere, its message naming `path`.
template <class F> void expect_input_error(const fs::path& path, F&& f, const char* what) {
  bool thrown = false, named = false;
  std::string message;
  try {
    f();
  } catch (const InputError& e) {
    thrown = true;
    message = e.what();
    named = message.find(path.string()) != std::string::npos;
  } catch (const std::exception& e) {
    message = std::string("wrong exception type: ") + e.what();
  }
  EXPECT_TRUE(thrown) << what << ": " << message;
  EXPECT_TRUE(named) << what << ": message does not name the file: " << message;
  EXPECT_TRUE(all_ranks(thrown)) << what << ": not thrown on every rank";
}

template <class T> class Hdf5Store : public ::testing::Test {};
using Dimensions = ::testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(Hdf5Store, Dimensions);

TYPED_TEST(Hdf5Store, RoundTripIsBitExactOnAnyRankCount) {
  constexpr int dim = TypeParam::value;
  const auto dir = scratch("roundtrip" + std::to_string(dim));
  const auto path = dir / "sample.h5";
  const auto s = random_sample<dim>(1000, 2500, 17 + dim);
  const auto mine = my_part(s, /*last_has_contacts=*/false);
  write_configuration(MPI_COMM_WORLD, path, mine);
  EXPECT_TRUE(fs::exists(path));
  EXPECT_FALSE(fs::exists(temp_path_for(path)));

  // (a) all ranks of the writing communicator
  const auto all = read_configuration<dim>(MPI_COMM_WORLD, path);
  expect_matches(MPI_COMM_WORLD, s, all);
  // (b) rank 0 alone
  if (world_rank() == 0) {
    const auto one = read_configuration<dim>(MPI_COMM_SELF, path);
    expect_matches(MPI_COMM_SELF, s, one);
    const auto meta = read_file_meta(MPI_COMM_SELF, path);
    EXPECT_EQ(meta.dimension, dim);
    EXPECT_EQ(meta.n_particles, 1000);
    EXPECT_EQ(meta.n_contacts, 2500);
    EXPECT_EQ(meta.deck_text, s.meta.deck_text);
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

TYPED_TEST(Hdf5Store, EmptyRanksAndNoContacts) {
  constexpr int dim = TypeParam::value;
  const auto dir = scratch("empty" + std::to_string(dim));
  // All particles on rank 0, no contact anywhere.
  auto s = random_sample<dim>(37, 0, 5);
  s.meta.deck_text.clear();
  s.meta.stage_name.clear();
  Configuration<dim> c;
  c.cell = s.cell;
  c.meta = s.meta;
  if (world_rank() == 0)
    for (const auto& p : s.particles)
      c.particles.add_owned(p);
  write_configuration(MPI_COMM_WORLD, dir / "empty.h5", c);
  const auto back = read_configuration<dim>(MPI_COMM_WORLD, dir / "empty.h5");
  expect_matches(MPI_COMM_WORLD, s, back);

  // No particle at all.
  Sample<dim> none;
  none.cell = s.cell;
  Configuration<dim> z;
  z.cell = s.cell;
  write_configuration(MPI_COMM_WORLD, dir / "none.h5", z);
  const auto zb = read_configuration<dim>(MPI_COMM_WORLD, dir / "none.h5");
  EXPECT_EQ(zb.particles.size(), 0u);
  EXPECT_EQ(zb.contacts.size(), 0u);
  EXPECT_EQ(zb.meta.kind, "configuration");
  EXPECT_EQ(zb.meta.n_particles, 0);
}

TYPED_TEST(Hdf5Store, BadFilesThrowInputErrorOnEveryRank) {
  constexpr int dim = TypeParam::value;
  const auto dir = scratch("bad" + std::to_string(dim));
  const auto good = dir / "good.h5";
  write_configuration(MPI_COMM_WORLD, good, my_part(random_sample<dim>(200, 300, 3), true));

  const auto truncated = dir / "truncated.h5", garbage = dir / "garbage.h5",
             missing = dir / "missing.h5", no_radius = dir / "no_radius.h5",
             foreign = dir / "foreign.h5", directory = dir / "a_directory.h5",
             short_mass = dir / "short_mass.h5";
  if (world_rank() == 0) {
    const std::string bytes = file_bytes(good);
    std::ofstream(truncated, std::ios::binary).write(bytes.data(), bytes.size() / 2);
    std::mt19937 rng(1);
    std::string junk(4096, '\0');
    for (auto& ch : junk)
      ch = static_cast<char>(rng());
    std::ofstream(garbage, std::ios::binary).write(junk.data(), junk.size());
    fs::remove(missing);
    fs::copy_file(good, no_radius, fs::copy_options::overwrite_existing);
    hid_t f = H5Fopen(no_radius.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    EXPECT_GE(H5Ldelete(f, "/particles/radius", H5P_DEFAULT), 0);
    H5Fclose(f);
    // /particles/mass one row short of n_particles.
    fs::copy_file(good, short_mass, fs::copy_options::overwrite_existing);
    f = H5Fopen(short_mass.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    EXPECT_GE(H5Ldelete(f, "/particles/mass", H5P_DEFAULT), 0);
    const hsize_t rows = 199;
    std::vector<double> ones(rows, 1.0);
    hid_t space = H5Screate_simple(1, &rows, nullptr);
    hid_t d = H5Dcreate2(f, "/particles/mass", H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT,
                         H5P_DEFAULT);
    EXPECT_GE(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, ones.data()), 0);
    H5Dclose(d);
    H5Sclose(space);
    H5Fclose(f);
    hid_t g = H5Fcreate(foreign.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    H5Fclose(g);
    fs::create_directories(directory);
  }
  MPI_Barrier(MPI_COMM_WORLD);

  for (const auto& p : {truncated, garbage, missing, no_radius, foreign, directory, short_mass}) {
    expect_input_error(
        p, [&] { read_configuration<dim>(MPI_COMM_WORLD, p); }, p.filename().c_str());
  }
  for (const auto& p : {truncated, garbage, missing, foreign})
    expect_input_error(
        p, [&] { read_file_meta(MPI_COMM_WORLD, p); }, p.filename().c_str());
  // Wrong dimension.
  constexpr int other = dim == 2 ? 3 : 2;
  expect_input_error(
      good, [&] { read_configuration<other>(MPI_COMM_WORLD, good); }, "wrong dimension");
  // The detail names the missing object.
  try {
    read_configuration<dim>(MPI_COMM_WORLD, no_radius);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/particles/radius"), std::string::npos) << e.what();
  }
  try {
    read_configuration<dim>(MPI_COMM_WORLD, short_mass);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/particles/mass has shape [199]"), std::string::npos)
        << e.what();
  }
}

namespace {
/// Reads dataset `name` of the file at `path` whole, changes it with `change` and writes it
/// back (serial HDF5; rank 0 only).
template <class T, class F>
void poke(const fs::path& path, const char* name, hid_t type, F change) {
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
  const hid_t space = H5Dget_space(d);
  std::vector<T> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  EXPECT_GE(H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0);
  change(v);
  EXPECT_GE(H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0);
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
}
} // namespace

// Files that are well-formed HDF5 but contradict themselves: refused on every rank, with the
// same message whichever ranks' slices hold the offending rows (the id checks compare rows
// that different ranks read: the first and the last row).
TYPED_TEST(Hdf5Store, InconsistentFilesAreRefusedOnEveryRank) {
  constexpr int dim = TypeParam::value;
  const auto dir = scratch("inconsistent" + std::to_string(dim));
  const auto good = dir / "good.h5";
  write_configuration(MPI_COMM_WORLD, good, my_part(random_sample<dim>(200, 300, 7), true));
  struct Case {
    const char* file;
    const char* expected;
  };
  const Case cases[] = {
      {"duplicate_id.h5", "appears 2 times in /particles/id (ids must be unique)"},
      {"missing_grain.h5", "a contact names grain 1000000, which /particles/id does not hold"},
      {"nan_velocity.h5", "/particles/velocity row 3 holds nan (need finite values)"},
      {"negative_force.h5",
       "/contacts/normal_force row 5 = -1.000000 (the elastic normal force N^e is never negative"},
      {"zero_mass.h5", "/particles/mass or /particles/inertia row 2 = 0.000000"},
  };
  if (world_rank() == 0) {
    for (const auto& c : cases)
      fs::copy_file(good, dir / c.file, fs::copy_options::overwrite_existing);
    poke<std::int64_t>(dir / "duplicate_id.h5", "/particles/id", H5T_NATIVE_INT64,
                       [](auto& v) { v.back() = v.front(); });
    poke<std::int64_t>(dir / "missing_grain.h5", "/contacts/second", H5T_NATIVE_INT64,
                       [](auto& v) { v.back() = 1000000; });
    poke<double>(dir / "nan_velocity.h5", "/particles/velocity", H5T_NATIVE_DOUBLE,
                 [](auto& v) { v[3 * dim + 1] = std::numeric_limits<double>::quiet_NaN(); });
    poke<double>(dir / "negative_force.h5", "/contacts/normal_force", H5T_NATIVE_DOUBLE,
                 [](auto& v) { v[5] = -1.0; });
    poke<double>(dir / "zero_mass.h5", "/particles/mass", H5T_NATIVE_DOUBLE,
                 [](auto& v) { v[2] = 0.0; });
  }
  MPI_Barrier(MPI_COMM_WORLD);
  for (const auto& c : cases) {
    const auto p = dir / c.file;
    expect_input_error(
        p, [&] { read_configuration<dim>(MPI_COMM_WORLD, p); }, c.file);
    try {
      read_configuration<dim>(MPI_COMM_WORLD, p);
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(c.expected), std::string::npos)
          << c.file << ": " << e.what();
    }
  }
  // The unchanged file still reads.
  EXPECT_NO_THROW(read_configuration<dim>(MPI_COMM_WORLD, good));
}

TYPED_TEST(Hdf5Store, FailedWriteLeavesThePreviousFileUntouched) {
  constexpr int dim = TypeParam::value;
  const auto dir = scratch("atomic" + std::to_string(dim));
  const auto path = dir / "state.h5";
  const auto a = random_sample<dim>(300, 400, 100), b = random_sample<dim>(301, 401, 200);
  write_configuration(MPI_COMM_WORLD, path, my_part(a, true));
  const std::string before = world_rank() == 0 ? file_bytes(path) : std::string();

  // A failure in the middle of the write (after the particles, before the contacts).
  detail::set_hdf5_write_hook([](std::string_view stage) {
    if (stage == "after_particles")
      throw Error("simulated I/O failure");
  });
  bool thrown = false;
  try {
    write_configuration(MPI_COMM_WORLD, path, my_part(b, true));
  } catch (const Error& e) {
    thrown = std::string(e.what()).find("simulated I/O failure") != std::string::npos;
  }
  detail::set_hdf5_write_hook(nullptr);
  EXPECT_TRUE(all_ranks(thrown));
  if (world_rank() == 0) {
    EXPECT_EQ(file_bytes(path), before) << "the previous file was modified";
    EXPECT_FALSE(fs::exists(temp_path_for(path))) << "temp file left behind";
  }

  // A failure on the last rank only, as a full disk gives (MPI-IO reports it on the rank whose
  // write failed): every rank stops together (no hang in the next collective write), with the
  // write-failure code and a message naming the file.
  detail::set_hdf5_write_hook([](std::string_view stage) {
    if (stage == "after_particles" && world_rank() == world_size() - 1)
      throw Error("simulated disk full");
  });
  thrown = false;
  try {
    write_configuration(MPI_COMM_WORLD, path, my_part(b, true));
  } catch (const Error& e) {
    thrown = e.exit_code() == kExitWriteFailed &&
             std::string(e.what()).find("cannot write " + path.string() + ": ") == 0 &&
             std::string(e.what()).find("simulated disk full") != std::string::npos &&
             // The scratch disk has space and no ulimit -f applies: the likely cause named is
             // a quota, which statvfs cannot see.
             std::string(e.what()).find("most likely a disk quota (Disk quota exceeded, EDQUOT") !=
                 std::string::npos;
    if (!thrown)
      ADD_FAILURE() << e.exit_code() << ": " << e.what();
  }
  detail::set_hdf5_write_hook(nullptr);
  EXPECT_TRUE(all_ranks(thrown));
  if (world_rank() == 0) {
    EXPECT_EQ(file_bytes(path), before) << "the previous file was modified";
    EXPECT_FALSE(fs::exists(temp_path_for(path))) << "temp file left behind";
  }

  // An inconsistent configuration (contact with a negative id on the last rank only).
  auto bad = my_part(b, true);
  if (world_rank() == world_size() - 1)
    bad.contacts.insert({-4, 2}, ContactState<dim>{});
  thrown = false;
  try {
    write_configuration(MPI_COMM_WORLD, path, bad);
  } catch (const Error&) {
    thrown = true;
  }
  EXPECT_TRUE(all_ranks(thrown));
  if (world_rank() == 0) {
    EXPECT_EQ(file_bytes(path), before);
  }

  // While the write is in progress only the temp file is new; the old file is still there.
  bool during_ok = true;
  detail::set_hdf5_write_hook([&](std::string_view stage) {
    if (stage != "before_rename" || world_rank() != 0)
      return;
    during_ok = fs::exists(temp_path_for(path)) && file_bytes(path) == before;
  });
  write_configuration(MPI_COMM_WORLD, path, my_part(b, true));
  detail::set_hdf5_write_hook(nullptr);
  EXPECT_TRUE(during_ok);
  EXPECT_FALSE(fs::exists(temp_path_for(path)));
  const auto back = read_configuration<dim>(MPI_COMM_WORLD, path);
  expect_matches(MPI_COMM_WORLD, b, back);
}

// Every committed granpack file (docs/data/*.h5, jobs/runs/*/checkpoint.h5), written by this
// and earlier versions, still reads as `granpack info` reads it: describe_file on all ranks,
// a summary with a "particles:" line (tests/cli/hdf5_upstream.sh ran `info` on each before).
TEST(CommittedFiles, ReadAsInfoReadsThem) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(test::source_dir() / "docs/data"))
    if (e.is_regular_file() && e.path().extension() == ".h5")
      files.push_back(e.path());
  const fs::path runs = test::source_dir() / "jobs/runs";
  if (fs::is_directory(runs))
    for (const auto& e : fs::directory_iterator(runs))
      if (fs::is_regular_file(e.path() / "checkpoint.h5"))
        files.push_back(e.path() / "checkpoint.h5");
  std::sort(files.begin(), files.end()); // the same order on every rank
  EXPECT_GE(files.size(), 1u);
  for (const auto& f : files) {
    std::string text;
    try {
      text = describe_file(MPI_COMM_WORLD, f);
    } catch (const std::exception& e) {
      ADD_FAILURE() << f << ": " << e.what();
      continue;
    }
    EXPECT_TRUE(text.rfind("particles:", 0) == 0 || text.find("\nparticles:") != std::string::npos)
        << f << ":\n"
        << text;
  }
  if (world_rank() == 0)
    std::printf("[ committed ] %zu files read\n", files.size());
}

TYPED_TEST(Hdf5Store, DescribeAndXdmfSidecar) {
  constexpr int dim = TypeParam::value;
  const auto dir = scratch("describe" + std::to_string(dim));
  const auto path = dir / "look.h5";
  const auto s = random_sample<dim>(123, 45, 9);
  write_configuration(MPI_COMM_WORLD, path, my_part(s, true));
  const std::string text = describe_file(MPI_COMM_WORLD, path);
  EXPECT_NE(text.find("dimension:   " + std::to_string(dim)), std::string::npos) << text;
  EXPECT_NE(text.find("particles:   123"), std::string::npos) << text;
  EXPECT_NE(text.find("contacts:    45"), std::string::npos) << text;
  EXPECT_NE(text.find(dim == 2 ? "L = 1.5 x 2.25 m" : "L = 1.5 x 2.25 x 3.125 m"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("checkpoint"), std::string::npos) << text;

  const auto xdmf = xdmf_path_for(path);
  EXPECT_EQ(xdmf.filename(), "look.xdmf");
  const std::string x = file_bytes(xdmf);
  EXPECT_NE(x.find("Polyvertex"), std::string::npos);
  EXPECT_NE(x.find(">look.h5:/particles/position<"), std::string::npos) << x;
  EXPECT_NE(x.find(dim == 2 ? "GeometryType=\"XY\"" : "GeometryType=\"XYZ\""), std::string::npos);
  EXPECT_NE(x.find("NumberOfElements=\"123\""), std::string::npos);
  EXPECT_EQ(x.find(dir.string()), std::string::npos) << "sidecar should use a relative path";
}

} // namespace

namespace {
/// Dataset `name` of the file at `path`: its shape and its values as doubles (serial HDF5).
std::pair<std::vector<hsize_t>, std::vector<double>> read_whole(const fs::path& path,
                                                                const char* name) {
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
  const hid_t space = H5Dget_space(d);
  std::vector<hsize_t> dims(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  if (!v.empty()) {
    EXPECT_GE(H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0);
  }
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
  return {dims, v};
}
} // namespace

// The /network group (docs/hdf5-schema.md): each rank's contacts as one slice, the lines
// numbering the global point rows (2k, 2k + 1) whatever rank wrote row k, per-grain rows beside
// /particles; the sidecar then holds the contacts grid. Without it: no group, no contacts grid.
TYPED_TEST(Hdf5Store, NetworkGroupAndItsSidecarGrid) {
  constexpr int dim = TypeParam::value;
  const auto dir = scratch("network" + std::to_string(dim));
  const auto path = dir / "net.h5";
  auto c = my_part(random_sample<dim>(123, 45, 9), true);
  NetworkFields<dim> f;
  for (std::size_t k = 0; k < c.contacts.size(); ++k) {
    const double key = double(c.contacts.key(k).first) + 1e-3 * double(c.contacts.key(k).second);
    f.start.push_back(Vec<dim>::Constant(key));
    f.end.push_back(Vec<dim>::Constant(-key));
    f.normal_force.push_back(key);
    f.tangential_magnitude.push_back(2 * key);
    f.kind.push_back(static_cast<std::int64_t>(k % 4));
    f.mobilisation.push_back(0.25 * double(k % 5));
    f.strong.push_back(double(k % 2));
  }
  for (std::size_t i = 0; i < c.particles.n_owned(); ++i) {
    f.contacts.push_back(double(c.particles.id[i]));
    f.carrying_contacts.push_back(0.5 * double(c.particles.id[i]));
    f.mean_stress.push_back(-double(c.particles.id[i]));
    f.rattler.push_back(double(c.particles.id[i] % 2));
    f.fixed_rattler.push_back(double(c.particles.id[i] % 5 == 1));
    f.cluster_id.push_back(c.particles.id[i] / 10);
    f.bond_order.push_back(1e-3 * double(c.particles.id[i]));
    f.crystalline.push_back(double(c.particles.id[i] % 3 == 0));
    for (int a = 0; a < dim; ++a)
      f.net_force[a].push_back(double(c.particles.id[i]) + a);
    for (int a = 0; a < rot_dim<dim>; ++a)
      f.net_moment[std::size_t(a)].push_back(-double(c.particles.id[i]) - 0.5 * a);
    for (int k = 0; k < dim * dim; ++k)
      f.stress[std::size_t(k)].push_back(100.0 * double(c.particles.id[i]) + k);
  }
  c.network = f;
  write_configuration(MPI_COMM_WORLD, path, c);
  if (world_rank() == 0) {
    const auto [ldims, line] = read_whole(path, "/network/line");
    const auto [pdims, point] = read_whole(path, "/network/point");
    const auto [ndims, normal] = read_whole(path, "/network/normal_force");
    const auto [gdims, net] = read_whole(path, "/network/net_force");
    const auto [nmdims, moment] = read_whole(path, "/network/net_moment");
    constexpr std::size_t rd = rot_dim<dim>;
    ASSERT_EQ(nmdims, (std::vector<hsize_t>{123, rd}));
    const auto [cdims, count] = read_whole(path, "/network/contacts");
    const auto [rdims, rattler] = read_whole(path, "/network/rattler");
    const auto [fdims, fixed] = read_whole(path, "/network/fixed_rattler");
    ASSERT_EQ(fdims, (std::vector<hsize_t>{123}));
    const auto [sdims, stress] = read_whole(path, "/network/stress");
    const auto [kdims, cluster] = read_whole(path, "/network/cluster_id");
    const auto [odims, order] = read_whole(path, "/network/bond_order");
    ASSERT_EQ(kdims, (std::vector<hsize_t>{123}));
    ASSERT_EQ(odims, (std::vector<hsize_t>{123}));
    ASSERT_EQ(sdims, (std::vector<hsize_t>{123, dim * dim}));
    ASSERT_EQ(rdims, (std::vector<hsize_t>{123}));
    ASSERT_EQ(ldims, (std::vector<hsize_t>{45, 2}));
    ASSERT_EQ(pdims, (std::vector<hsize_t>{90, dim}));
    ASSERT_EQ(gdims, (std::vector<hsize_t>{123, dim}));
    ASSERT_EQ(cdims, (std::vector<hsize_t>{123}));
    for (std::size_t k = 0; k < 45; ++k) {
      EXPECT_EQ(line[2 * k], double(2 * k));
      EXPECT_EQ(line[2 * k + 1], double(2 * k + 1));
      EXPECT_EQ(point[2 * k * dim], normal[k]);        // start of contact k
      EXPECT_EQ(point[(2 * k + 1) * dim], -normal[k]); // its end
    }
    const auto [idims, ids] = read_whole(path, "/particles/id");
    for (std::size_t i = 0; i < 123; ++i) {
      EXPECT_EQ(count[i], ids[i]); // per-grain rows follow /particles
      EXPECT_EQ(rattler[i], double(std::int64_t(ids[i]) % 2));
      EXPECT_EQ(fixed[i], double(std::int64_t(ids[i]) % 5 == 1));
      EXPECT_EQ(cluster[i], double(std::int64_t(ids[i]) / 10));
      EXPECT_EQ(order[i], 1e-3 * ids[i]);
      EXPECT_EQ(net[i * dim + 1], ids[i] + 1);
      EXPECT_EQ(moment[i * rd + rd - 1], -ids[i] - 0.5 * double(rd - 1));
      for (std::size_t k = 0; k < dim * dim; ++k) // row-major sigma_ab, rows as /particles
        EXPECT_EQ(stress[i * dim * dim + k], 100.0 * ids[i] + double(k));
    }
    const std::string x = file_bytes(xdmf_path_for(path));
    EXPECT_NE(x.find("TopologyType=\"Polyline\" NumberOfElements=\"45\""), std::string::npos) << x;
    EXPECT_NE(x.find("Dimensions=\"90 " + std::to_string(dim) + "\""), std::string::npos) << x;
    EXPECT_NE(x.find(">net.h5:/network/net_force<"), std::string::npos) << x;
    EXPECT_NE(x.find(dim == 3 ? "Name=\"net_moment\" AttributeType=\"Vector\""
                              : "Name=\"net_moment\" AttributeType=\"Scalar\""),
              std::string::npos)
        << x;
    EXPECT_NE(x.find(">net.h5:/network/rattler<"), std::string::npos) << x;
    EXPECT_NE(x.find(">net.h5:/network/fixed_rattler<"), std::string::npos) << x;
    EXPECT_NE(x.find(">net.h5:/network/strong<"), std::string::npos) << x;
    EXPECT_NE(x.find("Name=\"cluster_id\" AttributeType=\"Scalar\""), std::string::npos) << x;
    EXPECT_NE(x.find(">net.h5:/network/crystalline<"), std::string::npos) << x;
    // ParaView's tensor is 9 components; 2D's 2 x 2 goes as a 4-component matrix.
    EXPECT_NE(x.find(dim == 3 ? "Name=\"stress\" AttributeType=\"Tensor\""
                              : "Name=\"stress\" AttributeType=\"Matrix\""),
              std::string::npos)
        << x;
    EXPECT_NE(
        x.find("Dimensions=\"123 " + std::to_string(dim * dim) +
               "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">net.h5:/network/stress<"),
        std::string::npos)
        << x;
    const auto [mdims, mob] = read_whole(path, "/network/mobilisation");
    ASSERT_EQ(mdims, (std::vector<hsize_t>{45}));
    EXPECT_NE(x.find("Name=\"contacts\" AttributeType=\"Scalar\" Center=\"Node\""),
              std::string::npos)
        << x;
  }
  // The same state without a network: neither the group nor the contacts grid.
  c.network.reset();
  write_configuration(MPI_COMM_WORLD, path, c);
  if (world_rank() == 0) {
    const hid_t fid = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    EXPECT_EQ(H5Lexists(fid, "network", H5P_DEFAULT), 0);
    H5Fclose(fid);
    EXPECT_EQ(file_bytes(xdmf_path_for(path)).find("Polyline"), std::string::npos);
  }
}

// A `read` stage keeps treatment II's flags (docs/visualisation.md): read_fixed_rattlers gives
// every rank the ids that /network/fixed_rattler flags, on any rank count; nothing for a file
// without /network; a flag other than 0 or 1 is refused on every rank, naming the file.
TYPED_TEST(Hdf5Store, FixedRattlersReadBack) {
  constexpr int dim = TypeParam::value;
  const auto dir = scratch("fixed" + std::to_string(dim));
  const auto s = random_sample<dim>(123, 45, 11);
  auto c = my_part(s, true);
  // Zeros of the right lengths (the writer checks them) but for the flags.
  const std::size_t n = c.particles.n_owned(), nc = c.contacts.size();
  NetworkFields<dim> f;
  f.reset(nc, n);
  f.strong.assign(nc, 0.0);
  for (auto* v : {&f.rattler, &f.bond_order, &f.crystalline})
    v->assign(n, 0.0);
  f.cluster_id.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    f.fixed_rattler.push_back(double(c.particles.id[i] % 3 == 0));
  std::vector<std::int64_t> want;
  for (const auto& p : s.particles)
    if (p.id % 3 == 0)
      want.push_back(p.id);
  std::sort(want.begin(), want.end());
  ASSERT_FALSE(want.empty());
  c.network = f;
  write_configuration(MPI_COMM_WORLD, dir / "fixed.h5", c);
  EXPECT_EQ(read_fixed_rattlers(MPI_COMM_WORLD, dir / "fixed.h5"), want);
  if (world_rank() == 0) {
    EXPECT_EQ(read_fixed_rattlers(MPI_COMM_SELF, dir / "fixed.h5"), want);
  }
  MPI_Barrier(MPI_COMM_WORLD);

  if (world_rank() == 0 && n > 0)
    c.network->fixed_rattler[0] = 0.5;
  write_configuration(MPI_COMM_WORLD, dir / "half.h5", c);
  expect_input_error(
      dir / "half.h5", [&] { read_fixed_rattlers(MPI_COMM_WORLD, dir / "half.h5"); },
      "a fixed_rattler flag of 0.5");

  c.network.reset();
  write_configuration(MPI_COMM_WORLD, dir / "none.h5", c);
  EXPECT_TRUE(read_fixed_rattlers(MPI_COMM_WORLD, dir / "none.h5").empty());
}
