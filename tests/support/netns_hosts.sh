# Two test hosts in network namespaces, for the multi-host tests (sourced, not run). The caller sets
#   tag (unique, e.g. $$), net (second octet of the 10.x test network), deploy (the deploy dir)
# and gets ns_a/ns_b, veth_a/veth_b, addr_a/addr_b; from netns_common.sh work (a temp dir), pids (background
# processes to end) and a cleanup trap that ends them and removes both namespaces (and with them the veth pair);
# and
# plant_profile ADDR: deploy/dds/plant.xml rewritten for this host (its own address, both hosts as peers),
# DDS-Security off (these tests measure the transport; tests/security covers the secured bus).
# Exits 77 (skipped) without permission to create namespaces.
source "$(dirname "${BASH_SOURCE[0]}")/netns_common.sh"

ns_a="ct${net}a_$tag"; ns_b="ct${net}b_$tag"; veth_a="v${net}a$tag"; veth_b="v${net}b$tag"
addr_a="10.$net.$(( tag % 200 )).1"; addr_b="10.$net.$(( tag % 200 )).2"
netns_create "$ns_a"; netns_create "$ns_b"
ip link add "$veth_a" type veth peer name "$veth_b"
ip link set "$veth_a" netns "$ns_a"; ip link set "$veth_b" netns "$ns_b"
ip -n "$ns_a" addr add "$addr_a/24" dev "$veth_a"; ip -n "$ns_b" addr add "$addr_b/24" dev "$veth_b"
ip -n "$ns_a" link set "$veth_a" up; ip -n "$ns_b" link set "$veth_b" up

plant_profile() {  # $1 = this host's address
  sed -e "s|<address>192.0.2.10</address>  <!-- this host's plant-network address -->|<address>$1</address>|" \
      -e "s|<address>192.0.2.10</address>  <!-- this host -->|<address>$1</address>|" \
      -e "s|<locator><udpv4><address>192.0.2.10</address></udpv4></locator>  <!-- sensor / replay host -->|<locator><udpv4><address>$addr_a</address></udpv4></locator>|" \
      -e "s|<locator><udpv4><address>192.0.2.11</address></udpv4></locator>  <!-- estimator host -->|<locator><udpv4><address>$addr_b</address></udpv4></locator>|" \
      -e "/192.0.2.12/d" -e "s|<value>/etc/causal-twin/security</value>|<value>off</value>|" "$deploy/dds/plant.xml"
}
plant_profile "$addr_a" > "$work/host_a.xml"; plant_profile "$addr_b" > "$work/host_b.xml"
grep -q "$addr_a" "$work/host_a.xml" && grep -q "$addr_b" "$work/host_b.xml" && ! grep -q "<address>192.0.2" "$work/host_b.xml" \
  || { echo "FAIL: plant.xml no longer has the expected shape"; exit 1; }
