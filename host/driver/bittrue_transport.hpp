// In-process transport to the bit-true model (hls/rheo_kernel.hpp, hardware format): a
// command interpreter over the same frames the RTL core decodes, so both devices are
// driven by identical words. Its cycle counter advances by the documented cycles-per-step
// formula, the RTL's by the clocks it really spends.
#pragma once

#include <deque>
#include <memory>

#include "hls/edge_element.hpp"
#include "hls/rheo_kernel.hpp"
#include "host/driver/transport.hpp"

namespace rheo::driver {

class BitTrueTransport : public Transport {
 public:
  // element: the edge element of the modelled core (hls/edge_element.hpp).
  explicit BitTrueTransport(int lanes, const hls::EdgeElement& element = hls::kThreeElement);
  void send(const std::vector<std::uint32_t>& words) override;
  std::vector<std::uint32_t> receive(std::size_t n) override;
  std::string name() const override { return "bit-true model"; }

  const hls::CoreMemory& memory() const { return *mem_; }

 private:
  void process();
  void write_word(std::uint32_t region, std::uint32_t index, std::uint32_t field,
                  std::uint32_t word);
  std::uint32_t read_word(std::uint32_t region, std::uint32_t index, std::uint32_t field) const;

  int lanes_;
  hls::EdgeElement element_;
  std::unique_ptr<hls::CoreMemory> mem_;
  std::deque<std::uint32_t> in_;
  std::deque<std::uint32_t> out_;
  std::uint32_t cycles_ = 0;
};

}  // namespace rheo::driver
