#!/usr/bin/env bash
# Makes the files DDS Security needs, signed by a project CA made here with openssl:
#   OUT/ca.key.pem, ca.cert.pem              the CA (identities and permissions)
#   OUT/scanbus.key.pem, scanbus.cert.pem     the services' identity (CN=scanbus)
#   OUT/governance.p7s, permissions.p7s       config/dds/security/*.xml signed by the CA
#   OUT/secure.xml                            Fast DDS profile `secure`: PKI-DH
#                                             authentication, access control, AES-GCM
#                                             encryption, UDP on 127.0.0.1 only
# Give a process OUT/secure.xml with SCANBUS_DDS_PROFILE_FILE and SCANBUS_DDS_PROFILE=secure.
# Usage: scripts/make-security.sh OUT [IDENTITY_NAME]
set -euo pipefail
out=$1
name=${2:-scanbus}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
out=$(cd "$out" && pwd)
cd "$out"
if [ ! -f ca.key.pem ]; then
  openssl ecparam -name prime256v1 -genkey -noout -out ca.key.pem
  openssl req -x509 -new -key ca.key.pem -days 3650 -subj "/O=scanbus/CN=scanbus CA" -out ca.cert.pem 2> /dev/null
fi
openssl ecparam -name prime256v1 -genkey -noout -out "$name.key.pem"
openssl req -new -key "$name.key.pem" -subj "/O=scanbus/CN=$name" -out "$name.csr.pem" 2> /dev/null
openssl x509 -req -in "$name.csr.pem" -CA ca.cert.pem -CAkey ca.key.pem -CAcreateserial -days 3650 \
  -out "$name.cert.pem" 2> /dev/null
for document in governance permissions; do
  openssl smime -sign -text -in "$here/config/dds/security/$document.xml" -out "$document.p7s" \
    -signer ca.cert.pem -inkey ca.key.pem
done
sed -e "s|@OUT@|$out|g" -e "s|@NAME@|$name|g" "$here/config/dds/security/secure.xml.in" > "$name.secure.xml"
[ "$name" = scanbus ] && cp "$name.secure.xml" secure.xml
echo "wrote $out: CA, identity '$name', signed governance and permissions, profile $out/$name.secure.xml"
