#!/usr/bin/env bash
# DDS Security identities for an lpss cluster, made with openssl: an identity CA, a permissions CA, a signed
# governance (discovery and liveliness protected, every lpss topic's data and metadata encrypted), and an
# identity per role, each in a folder of its own that a program takes with --security FOLDER.
#
#   identities.sh init DIR [DAYS]           the two CAs, the governance, and coordinator, worker, observer and
#                                           operator identities (valid DAYS days, 365 by default)
#   identities.sh add DIR NAME ROLE [DAYS]  another identity of a role (a second operator, a worker per host)
#   identities.sh expired DIR NAME ROLE     an identity whose certificate has already expired (for tests)
#   identities.sh revoke DIR NAME           revokes NAME's certificate: every identity folder's crl.pem lists it
#
# Roles: coordinator (every topic), worker (sector frames, marks, results, sector requests), observer (reads
# the world; may ask for sectors whole), operator (an observer that may send commands). DIR/ca holds the CAs'
# private keys: keep it off the machines that run lpss. See docs/security.md.
set -euo pipefail

usage() { sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
[[ $# -ge 2 ]] || usage
command=$1
dir=$2
ca=$dir/ca

topics_all="lpss/sector_frames lpss/body_descriptions lpss/sector_owners lpss/worker_frames lpss/frame_go
lpss/commands lpss/command_results lpss/sector_requests lpss/status lpss/frame_acks"

# What each role may publish; every role may subscribe to every lpss topic but the commands (only the
# coordinator reads them) and the standby's acknowledgements.
publishes() {
    case $1 in
    coordinator) echo "lpss/sector_frames lpss/body_descriptions lpss/sector_owners lpss/worker_frames lpss/frame_go
lpss/command_results lpss/status lpss/frame_acks lpss/sector_requests" ;;
    worker) echo "lpss/sector_frames lpss/worker_frames lpss/command_results lpss/sector_requests" ;;
    observer) echo "lpss/sector_requests" ;;
    operator) echo "lpss/sector_requests lpss/commands" ;;
    *) echo "unknown role '$1' (coordinator, worker, observer, operator)" >&2; exit 2 ;;
    esac
}
subscribes() {
    case $1 in
    coordinator | worker) echo "$topics_all" ;;
    observer | operator) echo "lpss/sector_frames lpss/body_descriptions lpss/sector_owners lpss/worker_frames
lpss/frame_go lpss/command_results lpss/status" ;;
    esac
}

topic_list() { for t in $1; do printf '            <topic>%s</topic>\n' "$t"; done; }

openssl_config() {
    cat >"$ca/openssl.cnf" <<CNF
[ ca ]
default_ca = lpss_ca
[ lpss_ca ]
dir = $ca
database = \$dir/index.txt
serial = \$dir/serial
crlnumber = \$dir/crlnumber
new_certs_dir = \$dir/issued
certificate = \$dir/identity_ca.pem
private_key = \$dir/identity_ca.key
default_md = sha256
default_crl_days = 3650
policy = lpss_policy
unique_subject = no
copy_extensions = none
[ lpss_policy ]
organizationName = supplied
commonName = supplied
[ req ]
distinguished_name = req_dn
prompt = no
[ req_dn ]
O = lpss
CN = lpss
[ ca_ext ]
basicConstraints = critical, CA:true
keyUsage = critical, keyCertSign, cRLSign
# The permissions CA signs governance and permissions documents (S/MIME): that takes digitalSignature.
[ permissions_ca_ext ]
basicConstraints = critical, CA:true
keyUsage = critical, keyCertSign, cRLSign, digitalSignature
[ identity_ext ]
basicConstraints = CA:false
keyUsage = critical, digitalSignature, keyAgreement
CNF
}

# A self-signed CA: $1 name (identity_ca, permissions_ca), $2 its extensions' section.
make_ca() {
    openssl ecparam -name prime256v1 -genkey -noout -out "$ca/$1.key"
    openssl req -x509 -new -key "$ca/$1.key" -sha256 -days 3650 -subj "/O=lpss/CN=lpss $1" \
        -config "$ca/openssl.cnf" -extensions "$2" -out "$ca/$1.pem"
}

sign_smime() { # $1 xml in, $2 p7s out
    openssl smime -sign -in "$1" -text -out "$2" -signer "$ca/permissions_ca.pem" -inkey "$ca/permissions_ca.key"
}

governance() {
    cat >"$dir/governance.xml" <<XML
<?xml version="1.0" encoding="utf-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-Security/20170801/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>0</min><max>232</max></id_range></domains>
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>NONE</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>lpss/*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>ENCRYPT</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
XML
    sign_smime "$dir/governance.xml" "$dir/governance.p7s"
}

refresh_crl() {
    openssl ca -config "$ca/openssl.cnf" -gencrl -out "$ca/crl.pem" 2>/dev/null
    for d in "$dir"/*/; do
        [[ -f "$d/cert.pem" ]] && cp "$ca/crl.pem" "$d/crl.pem"
    done
    return 0
}

# An identity: $1 name, $2 role, $3 openssl ca date options.
make_identity() {
    local name=$1 role=$2 out=$dir/$1
    publishes "$role" >/dev/null
    [[ -e "$out" ]] && { echo "identity '$name' exists in $dir" >&2; exit 2; }
    mkdir -p "$out"
    openssl ecparam -name prime256v1 -genkey -noout -out "$out/key.pem"
    chmod 600 "$out/key.pem"
    openssl req -new -key "$out/key.pem" -subj "/O=lpss/CN=lpss-$name" -out "$out/request.csr"
    # shellcheck disable=SC2086
    openssl ca -batch -config "$ca/openssl.cnf" -extensions identity_ext $3 -in "$out/request.csr" \
        -out "$out/cert.pem" 2>/dev/null
    rm "$out/request.csr"
    local not_before not_after
    not_before=$(date -u -d "$(openssl x509 -in "$out/cert.pem" -noout -startdate | cut -d= -f2)" +%Y-%m-%dT%H:%M:%S)
    not_after=$(date -u -d "$(openssl x509 -in "$out/cert.pem" -noout -enddate | cut -d= -f2)" +%Y-%m-%dT%H:%M:%S)
    cat >"$out/permissions.xml" <<XML
<?xml version="1.0" encoding="utf-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-Security/20170801/omg_shared_ca_permissions.xsd">
  <permissions>
    <grant name="lpss-$name">
      <subject_name>CN=lpss-$name,O=lpss</subject_name>
      <validity><not_before>$not_before</not_before><not_after>$not_after</not_after></validity>
      <allow_rule>
        <domains><id_range><min>0</min><max>232</max></id_range></domains>
        <publish>
          <topics>
$(topic_list "$(publishes "$role")")
          </topics>
          <partitions><partition></partition><partition>lpss-from-*</partition></partitions>
        </publish>
        <subscribe>
          <topics>
$(topic_list "$(subscribes "$role")")
          </topics>
          <partitions><partition></partition><partition>lpss-from-*</partition></partitions>
        </subscribe>
      </allow_rule>
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
XML
    sign_smime "$out/permissions.xml" "$out/permissions.p7s"
    cp "$ca/identity_ca.pem" "$ca/permissions_ca.pem" "$dir/governance.p7s" "$out/"
    echo "$role" >"$out/role"
    refresh_crl
    echo "lpss: identity '$name' ($role) in $out"
}

case $command in
init)
    days=${3:-365}
    [[ -e "$ca" ]] && { echo "$dir already holds lpss identities ($ca exists)" >&2; exit 2; }
    mkdir -p "$ca/issued"
    chmod 700 "$ca"
    touch "$ca/index.txt"
    echo 1000 >"$ca/serial"
    echo 1000 >"$ca/crlnumber"
    openssl_config
    make_ca identity_ca ca_ext
    make_ca permissions_ca permissions_ca_ext
    governance
    for role in coordinator worker observer operator; do make_identity "$role" "$role" "-days $days"; done
    ;;
add)
    [[ $# -ge 4 ]] || usage
    make_identity "$3" "$4" "-days ${5:-365}"
    ;;
expired)
    [[ $# -ge 4 ]] || usage
    make_identity "$3" "$4" "-startdate 20200101000000Z -enddate 20200102000000Z"
    ;;
revoke)
    [[ $# -ge 3 ]] || usage
    [[ -f "$dir/$3/cert.pem" ]] || { echo "no identity '$3' in $dir" >&2; exit 2; }
    openssl ca -config "$ca/openssl.cnf" -revoke "$dir/$3/cert.pem" 2>/dev/null
    refresh_crl
    echo "lpss: identity '$3' revoked; every identity folder's crl.pem lists it"
    ;;
*) usage ;;
esac
