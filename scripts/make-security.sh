#!/usr/bin/env bash
# Makes the files DDS Security needs, signed by a project CA made here with openssl (its
# `ca` command: it keeps an index of what it signed, so certificates can be revoked):
#   OUT/ca.key.pem, ca.cert.pem, ca/        the CA (identities and permissions)
#   OUT/NAME.key.pem, NAME.cert.pem         one identity per service and `operator` (the
#                                           command line tools), CN=NAME,O=scanbus
#   OUT/governance.p7s                      config/dds/security/governance.xml, signed
#   OUT/permissions.p7s                     'scanbus security permissions' (each service may
#                                           publish and subscribe its catalogue topics only), signed
#   OUT/crl.pem                             the CA's revocation list (empty at first)
#   OUT/NAME.secure.xml                     Fast DDS profile `secure` with NAME's identity:
#                                           PKI-DH authentication (checked against crl.pem),
#                                           access control, AES-GCM encryption, UDP on
#                                           127.0.0.1 only; OUT/secure.xml is operator's
# A process runs with SCANBUS_DDS_PROFILE_FILE=OUT/NAME.secure.xml SCANBUS_DDS_PROFILE=secure.
# Usage: scripts/make-security.sh OUT [SCANBUS]              everything above
#        scripts/make-security.sh OUT [SCANBUS] --revoke NAME   NAME's certificate into crl.pem
#        scripts/make-security.sh OUT [SCANBUS] --expired NAME  OUT/NAME_expired.*: NAME's identity,
#                                                              valid 2020 to 2021 only (for tests)
# SCANBUS (the command, for the identities and permissions) defaults to build/services/cli/scanbus.
set -euo pipefail
out=$1
here=$(cd "$(dirname "$0")/.." && pwd)
scanbus=${2:-$here/build/services/cli/scanbus}
[ -x "$scanbus" ] && scanbus=$(realpath "$scanbus")  # before the cd below; else a command on PATH
action=${3:-}
name=${4:-}
mkdir -p "$out"
out=$(cd "$out" && pwd)
cd "$out"

ca() { openssl ca -batch -config ca/ca.cnf -cert ca.cert.pem -keyfile ca.key.pem "$@" 2> ca/last.log ||
  { cat ca/last.log; exit 1; }; }
# identity NAME FILE [openssl ca dates]: a key and a certificate CN=NAME signed by the CA.
identity() {
  openssl ecparam -name prime256v1 -genkey -noout -out "$2.key.pem"
  openssl req -new -key "$2.key.pem" -subj "/O=scanbus/CN=$1" -out "ca/$2.csr.pem" 2> /dev/null
  ca -notext -in "ca/$2.csr.pem" -out "$2.cert.pem" "${@:3}"
}
profile() {  # profile FILE: the secure profile with FILE's key and certificate
  sed -e "s|@OUT@|$out|g" -e "s|@NAME@|$1|g" "$here/config/dds/security/secure.xml.in" > "$1.secure.xml"
}

case "$action" in
  --revoke)
    ca -revoke "$name.cert.pem"
    ca -gencrl -out crl.pem
    echo "revoked '$name': $out/crl.pem lists it (processes read it when they start)"
    exit 0 ;;
  --expired)
    identity "$name" "${name}_expired" -startdate 20200101000000Z -enddate 20210101000000Z
    profile "${name}_expired"
    echo "wrote $out/${name}_expired.secure.xml: identity '$name', expired in 2021"
    exit 0 ;;
  "") ;;
  *) echo "make-security.sh: unknown action '$action' (--revoke NAME, --expired NAME)" >&2; exit 2 ;;
esac

mkdir -p ca/certs
if [ ! -f ca.key.pem ]; then
  openssl ecparam -name prime256v1 -genkey -noout -out ca.key.pem
  openssl req -x509 -new -key ca.key.pem -days 3650 -subj "/O=scanbus/CN=scanbus CA" -out ca.cert.pem 2> /dev/null
  : > ca/index.txt
  echo 1000 > ca/serial
  echo 1000 > ca/crlnumber
  cat > ca/ca.cnf <<CNF
[ ca ]
default_ca = scanbus_ca
[ scanbus_ca ]
dir = $out/ca
database = \$dir/index.txt
new_certs_dir = \$dir/certs
serial = \$dir/serial
crlnumber = \$dir/crlnumber
default_md = sha256
default_days = 3650
default_crl_days = 3650
policy = any_name
unique_subject = no
[ any_name ]
organizationName = supplied
commonName = supplied
CNF
fi
"$scanbus" security identities > ca/identities.txt
while read -r identity_name; do
  identity "$identity_name" "$identity_name"
  profile "$identity_name"
done < ca/identities.txt
cp operator.secure.xml secure.xml
"$scanbus" security permissions > ca/permissions.xml
openssl smime -sign -text -in "$here/config/dds/security/governance.xml" -out governance.p7s -signer ca.cert.pem -inkey ca.key.pem
openssl smime -sign -text -in ca/permissions.xml -out permissions.p7s -signer ca.cert.pem -inkey ca.key.pem
[ -f crl.pem ] || ca -gencrl -out crl.pem
echo "wrote $out: CA, identities $(tr '\n' ' ' < ca/identities.txt), signed governance and permissions, revocation list, a profile per identity"
