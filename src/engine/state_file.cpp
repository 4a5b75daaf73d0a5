#include "granpack/engine/state_file.h"

#include "granpack/comm/migration.h"
#include "granpack/engine/network_fields.h"

namespace granpack {

template <int dim>
void adopt_configuration(RunContext<dim>& ctx, Configuration<dim>&& c,
                         const std::array<int, dim>* grid,
                         const std::array<std::vector<double>, dim>* cuts) {
  ctx.system.cell = c.cell;
  ctx.system.particles = std::move(c.particles);
  ctx.system.contacts = std::move(c.contacts);
  ctx.decomposition = grid
                          ? std::make_unique<Decomposition<dim>>(ctx.world, *grid)
                          : std::make_unique<Decomposition<dim>>(ctx.world, ctx.system.cell.length);
  if (grid && cuts)
    ctx.decomposition->set_cuts(*cuts);
  distribute(ctx.system, *ctx.decomposition);
}

template <int dim>
Configuration<dim> state_configuration(const RunContext<dim>& ctx, const std::string& run_state) {
  Configuration<dim> c;
  c.cell = ctx.system.cell;
  c.particles = ctx.system.particles;
  c.particles.clear_ghosts();
  c.contacts = ctx.system.contacts;
  // Entries reset when a contact opened (age 0) wait in the store for the next compaction;
  // they are not contacts.
  c.contacts.erase_if([](const ContactKey&, const ContactState<dim>& s) { return s.age == 0; });
  c.meta.granpack_version = GRANPACK_VERSION;
  c.meta.dimension = dim;
  c.meta.time = ctx.system.time;
  c.meta.step = ctx.system.step;
  c.meta.stage_index = ctx.stage_index;
  c.meta.stage_name = ctx.stage_name;
  c.meta.deck_text = ctx.deck->text;
  c.meta.kind = run_state.empty() ? "configuration" : "checkpoint";
  c.meta.run_state = run_state;
  c.meta.parameters = ctx.parameters();
  // Configurations carry their contact network for viewers (the /network group, its XDMF
  // grid); checkpoints are restart state and stay as they were.
  if (run_state.empty())
    c.network = network_fields(ctx, c.contacts);
  return c;
}

template <int dim>
void write_state(RunContext<dim>& ctx, const std::filesystem::path& file,
                 const std::string& run_state) {
  ScopedPhase io(ctx.stage_timers.io);
  write_configuration<dim>(ctx.world, file, state_configuration(ctx, run_state));
}

template void adopt_configuration<2>(RunContext<2>&, Configuration<2>&&, const std::array<int, 2>*,
                                     const std::array<std::vector<double>, 2>*);
template void adopt_configuration<3>(RunContext<3>&, Configuration<3>&&, const std::array<int, 3>*,
                                     const std::array<std::vector<double>, 3>*);
template Configuration<2> state_configuration<2>(const RunContext<2>&, const std::string&);
template Configuration<3> state_configuration<3>(const RunContext<3>&, const std::string&);
template void write_state<2>(RunContext<2>&, const std::filesystem::path&, const std::string&);
template void write_state<3>(RunContext<3>&, const std::filesystem::path&, const std::string&);

} // namespace granpack
